"""NumPy references of the compiled map lattice kernels (:mod:`lenslab.warp.lattice`), for the tests.

Each function computes what its C++ kernel (``src/native/lattice.cpp``) computes, vectorised over nodes,
cells or samples but with every float64 step in the kernel's order: the kernels are built without fused
multiply-adds, so the tests hold them to these references bit for bit.
"""

from __future__ import annotations

import numpy as np

from lenslab.warp import lattice

#: Catmull-Rom basis: weight_i(t) = sum_a CR_BASIS[i, a] t^a
CR_BASIS = np.array([[0.0, -0.5, 1.0, -0.5], [1.0, 0.0, -2.5, 1.5], [0.0, 0.5, 2.0, -1.5], [0.0, 0.0, -0.5, 0.5]])


def ghost_nodes(nx, ny, valid, wrap: float):
    """``(gx, gy, have)``: invalid nodes next to valid ones extrapolated, an x pass then a y pass, each
    forwards then backwards: ``3 x1 - 3 x2 + x3`` from three known nodes in a line, ``2 x1 - x2`` from two
    (x unwrapped by ``wrap`` against the nearest); never within three nodes of the pass's start."""
    gx = np.array(nx, dtype=np.float64)
    gy = np.array(ny, dtype=np.float64)
    have = np.array(valid, dtype=bool)
    rows, cols = gx.shape
    for axis in (1, 0):
        known = have.copy()
        n = gx.shape[axis]
        for step in (1, -1):
            k = np.arange(n)
            ok_k = k >= 3 if step == 1 else k <= n - 4
            target = ~have & (ok_k[None, :] if axis == 1 else ok_k[:, None])
            a, b = np.nonzero(target)

            def at(m):  # the node m steps back along the pass
                return (a, b - m * step) if axis == 1 else (a - m * step, b)

            sel = known[at(1)] & known[at(2)]
            a, b = a[sel], b[sel]
            x1, x2, y1, y2 = gx[at(1)], gx[at(2)], gy[at(1)], gy[at(2)]
            if wrap > 0.0:
                x2 = x2 - wrap * np.round((x2 - x1) / wrap)
            three = known[at(3)]
            x3, y3 = gx[at(3)], gy[at(3)]
            if wrap > 0.0:
                x3 = x3 - wrap * np.round((x3 - x1) / wrap)
            gx[a, b] = np.where(three, 3.0 * x1 - 3.0 * x2 + x3, 2.0 * x1 - x2)
            gy[a, b] = np.where(three, 3.0 * y1 - 3.0 * y2 + y3, 2.0 * y1 - y2)
            have[a, b] = True
    return gx, gy, have


def cr_weights(t):
    """The four Catmull-Rom weights at fraction ``t``, in the kernels' order of operations."""
    t2 = t * t
    t3 = t2 * t
    return (0.5 * (-t3 + 2.0 * t2 - t), 0.5 * (3.0 * t3 - 5.0 * t2 + 2.0), 0.5 * (-3.0 * t3 + 4.0 * t2 + t),
            0.5 * (t3 - t2))


def _stencil(nodes, j, i, ref, wrap):
    """Node (cb + j, ca + i) of every cell, x unwrapped against each cell's ``ref`` when ``wrap`` > 0."""
    rows, cols = nodes.shape
    v = nodes[j:rows - 3 + j, i:cols - 3 + i]
    return v - wrap * np.floor((v - ref) / wrap + 0.5) if wrap > 0.0 else v


def lattice_grid(nx, ny, tx: float, ty: float, wrap: float):
    """Every cell's Catmull-Rom interpolant at ``(tx, ty)``: ``(ox, oy)`` float64 (rows - 3, cols - 3)."""
    wx, wy = cr_weights(float(tx)), cr_weights(float(ty))
    ref = nx[1:-2, 1:-2]
    sx = sy = 0.0
    for j in range(4):
        rx = ry = 0.0
        for i in range(4):
            rx = rx + wx[i] * _stencil(nx, j, i, ref, wrap)
            ry = ry + wx[i] * _stencil(ny, j, i, ref, 0.0)
        sx = sx + wy[j] * rx
        sy = sy + wy[j] * ry
    return sx, sy


def cell_coefficients(nodes, state, cb0: int, cb1: int, wrap: float) -> np.ndarray:
    """``coef`` (cb1 - cb0, ncx, K, 4, 4): ``CR^T P CR`` of each interpolating cell's 4x4 stencil ``P`` (x, y
    for state 1, the direction for state 2; x unwrapped), ``c[b, a]`` of tx^a ty^b; zeros elsewhere."""
    nk = nodes.shape[0]
    ncx = state.shape[1]
    coef = np.zeros((cb1 - cb0, ncx, nk, 4, 4))
    for q in range(nk):
        ref = nodes[q, 1:-2, 1:-2]
        p = np.stack([np.stack([_stencil(nodes[q], j, i, ref, wrap if q == 0 else 0.0) for i in range(4)], -1)
                      for j in range(4)], -2)[cb0:cb1]  # (rows, ncx, 4 j, 4 i)
        t = np.zeros(p.shape)
        for a in range(4):  # t = p CR, summed over i in order
            acc = 0.0
            for i in range(4):
                acc = acc + p[..., :, i] * CR_BASIS[i, a]
            t[..., :, a] = acc
        c = np.zeros(p.shape)
        for b in range(4):  # c = CR^T t, summed over j in order
            acc = 0.0
            for j in range(4):
                acc = acc + CR_BASIS[j, b] * t[..., j, :]
            c[..., b, :] = acc
        st = state[cb0:cb1]
        used = (st == 1) if q < 2 else (st == 2)
        coef[:, :, q][used] = c[used]
    return coef


def _cells(p, n):
    return np.clip(np.floor(p), 0, n - 1).astype(np.int64)


def _store(st, x, y, d, shape):
    """The band's arrays from each sample's cell state, position (state 1) and direction (state 2)."""
    xs = np.where(st == 1, x - 0.5, 0.0).astype(np.float32).reshape(shape)
    ys = np.where(st == 1, y - 0.5, 0.0).astype(np.float32).reshape(shape)
    need = np.select([st == 2, st == 0], [2, 1], 0).astype(np.int8).reshape(shape)
    dirs = np.where((st == 2)[:, None], d, np.nan).reshape(shape + (3,))
    return xs, ys, (st == 1).reshape(shape), need, dirs


def lattice_eval(coef, state, cb0: int, step: float, r0: int, offs, shape):
    """The map of a band of ``shape`` (h, W, S) with per-pixel offsets ``offs`` (ho, wo, S, 2): ``(xs, ys,
    valid, need, dirs)``, ``dirs`` NaN where the kernel leaves it; each component's bicubic by Horner's rule
    in tx inside ty."""
    h, w, n = shape
    ncy, ncx = state.shape
    r, c, k = (a.reshape(-1) for a in np.meshgrid(np.arange(h), np.arange(w), np.arange(n), indexing="ij"))
    o = offs[r % offs.shape[0], c if offs.shape[1] > 1 else 0, k]
    inv = 1.0 / step
    px = (c.astype(np.float64) + o[:, 0]) * inv
    py = ((r0 + r).astype(np.float64) + o[:, 1]) * inv
    ca, cb = _cells(px, ncx), _cells(py, ncy)
    st = state[cb, ca]
    tx, ty = px - ca, py - cb

    def poly(q):
        cf = coef[cb - cb0, ca, min(q, coef.shape[2] - 1)]
        acc = 0.0
        for b in range(3, -1, -1):
            acc = acc * ty + (((cf[:, b, 3] * tx + cf[:, b, 2]) * tx + cf[:, b, 1]) * tx + cf[:, b, 0])
        return acc

    d = np.stack([poly(2), poly(3), poly(4)], -1) if coef.shape[2] >= 5 else np.zeros((len(st), 3))
    return _store(st, poly(0), poly(1), d, shape)


def lattice_rows(coef, state, cb0: int, inv: float, r0: int, offs, shape):
    """The map of a band with offsets shared by every pixel (``offs`` (1, 1, S, 2)): each cell's bicubic first
    collapsed to a cubic in tx along the row (Horner in ty), then that cubic at tx."""
    h, w, n = shape
    ncy, ncx = state.shape
    r, c, k = (a.reshape(-1) for a in np.meshgrid(np.arange(h), np.arange(w), np.arange(n), indexing="ij"))
    o = offs[0, 0, k]
    py = ((r0 + r).astype(np.float64) + o[:, 1]) * inv
    cb = _cells(py, ncy)
    ca = _cells((c.astype(np.float64) + o[:, 0]) * inv, ncx)
    st = state[cb, ca]
    ty = py - cb
    tx = (c.astype(np.float64) + o[:, 0]) * inv - ca

    def cubic(q):
        cf = coef[cb - cb0, ca, min(q, coef.shape[2] - 1)]
        rc = [((cf[:, 3, a] * ty + cf[:, 2, a]) * ty + cf[:, 1, a]) * ty + cf[:, 0, a] for a in range(4)]
        return ((rc[3] * tx + rc[2]) * tx + rc[1]) * tx + rc[0]

    d = np.stack([cubic(2), cubic(3), cubic(4)], -1) if coef.shape[2] >= 5 else np.zeros((len(st), 3))
    return _store(st, cubic(0), cubic(1), d, shape)


def place(at, xy, v, xs, ys, valid) -> None:
    """Mapped samples into flat maps (float32 ``xs, ys``, bool ``valid``) at positions ``at``: ``xy - 0.5`` in
    float64 rounded to float32 where ``v``, else 0."""
    xs[at] = np.where(v, xy[:, 0] - 0.5, 0.0)
    ys[at] = np.where(v, xy[:, 1] - 0.5, 0.0)
    valid[at] = v


def outside_field(field, dirs: np.ndarray, have_ray: np.ndarray, seen: np.ndarray) -> np.ndarray | None:
    """:func:`lenslab.warp.lattice.outside_field` in NumPy, the same steps in the same order (its arc cosines from
    NumPy's own loops, the kernel's from glibc's vector maths, each within a few ulps: the same cells unless a bound
    falls within a few ulps of a cone's edge, beyond the 1e-9 rad of slack both add)."""
    if field is None:
        return None
    ny, nx = have_ray.shape
    ncy, ncx = ny - 3, nx - 3
    quad = ((1, 1), (1, 2), (2, 1), (2, 2))

    def at(m, i, j):
        return m[i:i + ncy, j:j + ncx]

    cand = np.ones((ncy, ncx), dtype=np.bool_)
    for i, j in quad:
        cand &= at(have_ray, i, j) & ~at(seen, i, j)
    out = np.zeros((ncy, ncx), dtype=np.bool_)
    if not cand.any():
        return out
    planes = [np.ascontiguousarray(dirs[..., k]) for k in range(3)]
    centre = [at(p, 1, 1) + at(p, 1, 2) + at(p, 2, 1) + at(p, 2, 2) for p in planes]
    norm = np.sqrt(centre[0] ** 2 + centre[1] ** 2 + centre[2] ** 2)
    cand &= norm > 1.0  # four rays that nearly cancel (a cell spanning half the sphere) have no bound
    norm[~cand] = 1.0
    for c in centre:
        c /= norm
    cos_r = np.full((ncy, ncx), 1.0)
    dot, part = np.empty((ncy, ncx)), np.empty((ncy, ncx))  # (reused: fresh pages cost more than the arithmetic)
    for i, j in quad:
        np.multiply(centre[0], at(planes[0], i, j), out=dot)
        for k in (1, 2):
            dot += np.multiply(centre[k], at(planes[k], i, j), out=part)
        np.minimum(cos_r, dot, out=cos_r)
    radius = np.arccos(np.clip(cos_r, -1.0, 1.0, out=cos_r), out=cos_r)
    radius *= lattice.CELL_BOUND
    radius += lattice.FIELD_SLACK
    for axis, angle in zip(np.asarray(field.axes, np.float64), np.asarray(field.angles, np.float64)):
        np.multiply(centre[0], axis[0], out=dot)
        for k in (1, 2):
            dot += np.multiply(centre[k], axis[k], out=part)
        off = np.arccos(np.clip(dot, -1.0, 1.0, out=dot), out=dot)
        off -= radius
        out |= off > angle
    out &= cand
    return out
