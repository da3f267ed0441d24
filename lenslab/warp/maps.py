"""Sampling maps: where each output sample reads the source, computed in float64.

For every output sample at continuous pixel position ``p`` (pixel centres at +0.5)::

    d_dst = dst.lens.pixel_to_dir(p)          # camera space of the output
    d_src = R d_dst,  R = R_src^T R_dst        # into the source's camera space
    q     = src.lens.dir_to_pixel(d_src)       # continuous source pixel position

and the sample is valid where both steps are. Samplers take *index* coordinates ``q - 0.5`` (the
centre of source pixel ``(i, j)`` at ``(i, j)``), stored as float32: at 16384 pixels float32 still
resolves 1/1000 of a pixel.

Evaluating the lens models for every output sample is the costly part of a warp, so by default the
map is evaluated exactly on a lattice of nodes every ``step`` output pixels and interpolated in
between (bicubic Catmull-Rom, in float64, the seam unwrapped). A lattice cell is interpolated only
where that is safe: its 4 corners are valid, its 16 stencil nodes have values (invalid nodes just
outside the valid region get extrapolated ghost values) and the interpolation agrees with the exact map
at four interior check points (t = 1/4, 3/4 on each axis) to within ``tol`` source pixels (default
1/500; the largest error measured anywhere in such cells is about 1/350, checked at every pixel by the
tests to 1/200, and to 1/50 near singular points). Errors are
measured on the sphere: for an equirect source an error in x counts cos(latitude) times (its columns
crowd together toward the poles), in units of the source's row height.

For a full-sphere equirect source, a cell that fails (near a pole, where longitude is singular) gets a
second chance: the ray *direction* is interpolated instead (smooth there) and projected exactly. A cell
whose 16 nodes and check points all lie where the output lens has no ray (outside a fisheye's circle)
is empty. Every other cell (the rim of a fisheye, a fold of a distortion model, a strongly curved swirl)
is computed exactly, sample by sample; so are tiled and cube-map cameras, whose maps jump between
tiles and faces. ``exact=True`` skips the lattice altogether.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numba
import numpy as np

from lenslab.errors import WarpError
from lenslab.lenses import Camera, rotation_between, sample_offsets
from lenslab.warp.dispatch import kernel, run_bands

#: Lens models whose maps are piecewise (tiles, cube faces): never interpolated across cells.
PIECEWISE_MODELS = frozenset({"tiled", "cubemap"})

LATTICE_STEP = 8  # output pixels between lattice nodes
#: where each lattice cell's interpolation is checked against the exact map (fractions of the cell)
CHECK_POINTS = ((0.25, 0.25), (0.75, 0.25), (0.25, 0.75), (0.75, 0.75))
LATTICE_TOL = 2e-3  # source pixels: the largest interpolation error a lattice cell may show at its checks


class ParallaxWarning(UserWarning):
    """A view from an eye point other than the source's was warped anyway (allow_parallax=True)."""


def world_eyes(camera: Camera) -> np.ndarray:
    """The distinct eye points (world space) a camera's rays start from, shape (n, 3)."""
    offsets = np.asarray(camera.lens.eye_offsets, dtype=np.float64).reshape(-1, 3)
    return camera.pose.eye + offsets @ camera.pose.rotation.T


def check_eyes(src: Camera, dst: Camera, allow_parallax: bool = False) -> float:
    """Check that every ray of ``dst`` starts at the source's eye; return the largest distance.

    A panorama records the light arriving at one point. A view from another point (a tile of a
    multi-view camera at its own position) would show near objects shifted against far ones
    (parallax), which no reprojection of that panorama can recreate: that is a :class:`WarpError`,
    or a :class:`ParallaxWarning` with ``allow_parallax=True`` (every ray is then treated as leaving
    from the source's eye).
    """
    se, de = world_eyes(src), world_eyes(dst)
    scale = 1.0 + max(float(np.abs(se).max()), float(np.abs(de).max()))
    gap = float(np.max(np.linalg.norm(de[:, None, :] - se[None, :, :], axis=-1)))
    if gap <= 1e-9 * scale:
        return 0.0
    msg = (
        f"the output camera sees from {len(de)} eye point(s) up to {gap:.6g} away from the source's eye "
        f"{tuple(round(float(v), 6) for v in se[0])}: a panorama records the light arriving at one point, so a "
        "view from anywhere else would need parallax (near objects shift against far ones) that no "
        "reprojection can recreate. Render such views with the tracer or give one source image per eye; "
        "to warp anyway, as if every eye were at the source's (allow_parallax=True, --allow-parallax)"
    )
    if len(se) > 1 and gap > 1e-9 * scale:
        msg = "the source camera has several eye points; " + msg
    if not allow_parallax:
        raise WarpError(msg)
    warnings.warn(msg.replace("to warp anyway, as if", "warping anyway, as if"), ParallaxWarning, stacklevel=3)
    return gap


def exact_map(src: Camera, dst: Camera, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Exact source pixel positions (float64, ``(..., 2)``) and validity of output positions ``points``."""
    xy, valid, _ = exact_map_parts(src, dst, points)
    return xy, valid


def exact_map_parts(src: Camera, dst: Camera, points: np.ndarray, with_dirs: bool = False):
    """Like :func:`exact_map`, plus whether the output ray itself exists (``dst`` validity alone)
    and, with ``with_dirs``, the ray directions in the source's camera space."""
    d, valid_dst = dst.lens.pixel_to_dir(points)
    r = rotation_between(src, dst)
    if not np.array_equal(r, np.eye(3)):
        d = d @ r.T
    xy, valid_src = src.lens.dir_to_pixel(d)  # zero where invalid (a zero direction is invalid)
    if with_dirs:
        return xy, valid_dst & valid_src, valid_dst, d
    return xy, valid_dst & valid_src, valid_dst


@dataclass
class MapBand:
    """The map of output rows ``r0:r1``: source index coordinates (float32) and validity per sample."""

    r0: int
    r1: int
    xs: np.ndarray  # (h, W, S) float32, source column index (centre of column i at i)
    ys: np.ndarray  # (h, W, S) float32
    valid: np.ndarray  # (h, W, S) bool

    @property
    def nbytes(self) -> int:
        return self.xs.nbytes + self.ys.nbytes + self.valid.nbytes


def wrap_width(src: Camera) -> float:
    """Period of the source's x coordinate (W for a full-turn equirect, else 0: no wrap)."""
    lens = src.lens
    return float(lens.width) if getattr(lens, "name", "") == "equirect" and getattr(lens, "wraps", False) else 0.0


class Mapper:
    """Computes maps from ``dst`` output positions into ``src`` pixels, band by band.

    ``offsets`` are the sub-pixel sample positions: shape ``(S, 2)`` (the same in every pixel) or
    ``(h, W, S, 2)`` per band (jittered); see :meth:`map_band`.
    """

    def __init__(self, src: Camera, dst: Camera, exact: bool = False, step: int = LATTICE_STEP,
                 tol: float = LATTICE_TOL):
        self.src, self.dst = src, dst
        self.width, self.height = dst.size
        self.wrap = wrap_width(src)
        piecewise = {src.lens.name, dst.lens.name} & PIECEWISE_MODELS
        self.step = int(step)
        self.tol = float(tol)
        lens = src.lens
        self.sphere = getattr(lens, "name", "") == "equirect" and getattr(lens, "full_sphere", False)
        self.lattice = None
        if not exact and not piecewise and self.width * self.height >= 16 * self.step * self.step:
            self.lattice = self._build_lattice()

    # -- lattice ---------------------------------------------------------------------------
    def _build_lattice(self):
        s = self.step
        ncx = -(-self.width // s)
        ncy = -(-self.height // s)
        xn = (np.arange(ncx + 3, dtype=np.float64) - 1.0) * s
        yn = (np.arange(ncy + 3, dtype=np.float64) - 1.0) * s
        pts = np.stack(np.meshgrid(xn, yn, indexing="xy"), axis=-1)
        # the exact map at the nodes and at the four check points of every cell, one set per thread
        checks = [np.stack(np.meshgrid((np.arange(ncx) + tx) * s, (np.arange(ncy) + ty) * s, indexing="xy"), axis=-1)
                  for tx, ty in CHECK_POINTS]
        exact = run_bands([(pts, True)] + [(g, False) for g in checks],
                          lambda job: _chunked(self.src, self.dst, *job))
        xy, v, vd, dirs = exact[0]
        nx, ny, have = _ghost_nodes(xy[..., 0], xy[..., 1], v, self.wrap)
        win = np.lib.stride_tricks.sliding_window_view

        def corners(m):
            return m[1:-2, 1:-2] & m[2:-1, 1:-2] & m[1:-2, 2:-1] & m[2:-1, 2:-1]

        # a cell interpolates when its 4 corners are valid and its 16 stencil nodes have values
        # (invalid nodes just outside the valid region get extrapolated ghost values; the checks
        # below decide whether the result is good enough)
        ok = win(have, (4, 4)).all(axis=(-1, -2)) & corners(v)
        dead = ~win(vd, (4, 4)).any(axis=(-1, -2))  # no output ray anywhere near
        nodes = [nx, ny]
        if self.sphere:
            # second chance for cells near a pole: interpolate the ray direction (smooth there) and
            # project it exactly; only where the output rays exist
            gd = [_ghost_nodes(dirs[..., k], dirs[..., k], vd, 0.0) for k in range(3)]
            nodes += [g[0] for g in gd]
            ok_dir = win(gd[0][2], (4, 4)).all(axis=(-1, -2)) & corners(vd)
        # check at four interior points of each cell (the centre alone is a blind spot: Catmull-Rom's
        # error is odd about it)
        for (tx, ty), (exy, ev, evd) in zip(CHECK_POINTS, exact[1:]):
            ix, iy = _lattice_grid(nx, ny, tx, ty, self.wrap)
            ok &= ev & self._close(ix, iy, exy)
            dead &= ~evd
            if self.sphere:
                d = np.stack([_lattice_grid(n, n, tx, ty, 0.0)[0] for n in nodes[2:]], axis=-1)
                px, py = _sphere_project(d, self.src.lens.width, self.src.lens.height)
                ok_dir &= ev & self._close(px, py, exy)
        state = np.where(ok, 1, np.where(dead, -1, 0)).astype(np.int8)
        if self.sphere:
            state[(state == 0) & ok_dir] = 2
        return np.stack(nodes), state

    def _close(self, ix, iy, exy) -> np.ndarray:
        """Interpolated positions within ``tol`` of the exact ones (measured on the sphere)."""
        dx = ix - exy[..., 0]
        if self.wrap:
            dx -= self.wrap * np.round(dx / self.wrap)
        dx *= self._x_scale(exy[..., 1])
        return (np.abs(dx) <= self.tol) & (np.abs(iy - exy[..., 1]) <= self.tol)

    def _x_scale(self, y: np.ndarray) -> np.ndarray | float:
        """Length on the sphere of one source column at row ``y``, in pixels (cos(latitude) for equirect).

        Map errors are judged by the distance they move a sample on the sphere: near a pole an equirect's
        columns crowd together, and a large error in x is a small one there.
        """
        lens = self.src.lens
        if getattr(lens, "name", "") != "equirect":
            return 1.0
        lat = np.radians(lens.lat_max - (y / lens.height) * (lens.lat_max - lens.lat_min))
        return np.abs(np.cos(lat)) * (np.radians(lens.lon_max - lens.lon_min) / lens.width) / (
            np.radians(lens.lat_max - lens.lat_min) / lens.height)

    def _coefficients(self, cb0: int, cb1: int) -> np.ndarray:
        """Bicubic coefficients of cell rows ``cb0:cb1``: ``(rows, ncx, K, 4, 4)``, ``c[.., k, b, a]`` of
        tx^a ty^b, for K = 2 components (x, y) or 5 (x, y and the direction) on a sphere source."""
        nodes, state = self.lattice
        coef = np.zeros((cb1 - cb0, state.shape[1], nodes.shape[0], 4, 4))
        _cell_coefficients(nodes, state, cb0, cb1, self.wrap, _CR, coef)
        return coef

    @property
    def lattice_fraction(self) -> float:
        """Fraction of the output's lattice cells that are interpolated (the rest is computed exactly)."""
        return 0.0 if self.lattice is None else float((self.lattice[1] > 0).mean())

    # -- bands -----------------------------------------------------------------------------
    def map_band(self, r0: int, r1: int, offsets: np.ndarray) -> MapBand:
        """The map of output rows ``r0:r1`` at sub-pixel ``offsets`` ((S, 2) or (h, W, S, 2), in [0, 1])."""
        offsets = np.asarray(offsets, dtype=np.float64)
        if offsets.ndim == 2:
            offsets = offsets[None, None]
        h, w = r1 - r0, self.width
        n = offsets.shape[2]
        xs = np.empty((h, w, n), dtype=np.float32)
        ys = np.empty((h, w, n), dtype=np.float32)
        valid = np.empty((h, w, n), dtype=np.bool_)
        if self.lattice is None:  # every sample exactly
            pts = np.empty((h, w, n, 2), dtype=np.float64)
            pts[..., 0] = np.arange(w, dtype=np.float64)[None, :, None] + offsets[..., 0]
            pts[..., 1] = np.arange(r0, r1, dtype=np.float64)[:, None, None] + offsets[..., 1]
            xy, v = exact_map(self.src, self.dst, pts)
            xs[...] = xy[..., 0] - 0.5
            ys[...] = xy[..., 1] - 0.5
            valid[...] = v
            xs[~v] = 0.0
            ys[~v] = 0.0
            return MapBand(r0, r1, xs, ys, valid)
        state = self.lattice[1]
        cb0 = max(0, int(np.floor((r0 + offsets[..., 1].min()) / self.step)))
        cb1 = min(state.shape[0], int(np.floor((r1 - 1 + offsets[..., 1].max()) / self.step)) + 1)
        need = np.empty((h, w, n), dtype=np.bool_)
        if offsets.shape[:2] == (1, 1):  # the same offsets in every pixel (the common case)
            _lattice_rows(self._coefficients(cb0, cb1), state, cb0, 1.0 / self.step, r0, offsets,
                          float(self.src.width), float(self.src.height), xs, ys, valid, need)
        else:
            _lattice_eval(self._coefficients(cb0, cb1), state, cb0, float(self.step), r0, offsets,
                          float(self.src.width), float(self.src.height), xs, ys, valid, need)
        flat = np.flatnonzero(need)
        if len(flat):  # the cells the lattice cannot serve, sample by sample
            r, c, k = np.unravel_index(flat, need.shape)
            o = offsets[r % offsets.shape[0], c % offsets.shape[1], k]
            xy, v = exact_map(self.src, self.dst, np.stack([c + o[:, 0], r0 + r + o[:, 1]], axis=-1))
            xs.reshape(-1)[flat] = np.where(v, xy[:, 0] - 0.5, 0.0)
            ys.reshape(-1)[flat] = np.where(v, xy[:, 1] - 0.5, 0.0)
            valid.reshape(-1)[flat] = v
        return MapBand(r0, r1, xs, ys, valid)


EXACT_CHUNK = 1 << 16  # points per call of the lens models while building a lattice (bounds the working set)


def _chunked(src: Camera, dst: Camera, points: np.ndarray, with_dirs: bool):
    """:func:`exact_map_parts` over a grid of points, ``EXACT_CHUNK`` rows of points at a time."""
    shape = points.shape[:-1]
    flat = points.reshape(-1, 2)
    parts = [exact_map_parts(src, dst, flat[i:i + EXACT_CHUNK], with_dirs)
             for i in range(0, len(flat), EXACT_CHUNK)]
    return tuple(np.concatenate([p[k] for p in parts]).reshape(shape + parts[0][k].shape[1:])
                 for k in range(len(parts[0])))


def _ghost_nodes(nx, ny, valid, wrap):
    """Fill invalid lattice nodes next to valid ones by extrapolation (an x pass, then a y pass):
    quadratic from three valid neighbours in a line, linear from two.

    Returns the filled x and y node values (C-contiguous float64) and which nodes now have a value.
    """
    gx, gy, have = nx.copy(), ny.copy(), valid.copy()
    for axis in (1, 0):
        known = have.copy()
        for step in (1, -1):
            def shifted(a, k):
                return np.roll(a, k * step, axis=axis)

            two = ~have & shifted(known, 1) & shifted(known, 2)
            # np.roll wraps around the lattice's edges: never extrapolate from the other side
            edge = [slice(None)] * 2
            edge[axis] = slice(0, 3) if step == 1 else slice(-3, None)
            two[tuple(edge)] = False
            if not two.any():
                continue
            three = two & shifted(known, 3)
            x1, x2, x3 = shifted(gx, 1), shifted(gx, 2), shifted(gx, 3)
            if wrap:  # unwrap the neighbours relative to the nearest
                x2 = x2 - wrap * np.round((x2 - x1) / wrap)
                x3 = x3 - wrap * np.round((x3 - x1) / wrap)
            y1, y2, y3 = shifted(gy, 1), shifted(gy, 2), shifted(gy, 3)
            gx[two] = np.where(three, 3 * x1 - 3 * x2 + x3, 2 * x1 - x2)[two]
            gy[two] = np.where(three, 3 * y1 - 3 * y2 + y3, 2 * y1 - y2)[two]
            have |= two
    return np.ascontiguousarray(gx), np.ascontiguousarray(gy), have


def sample_pattern(samples: int) -> np.ndarray:
    """Fixed stratified sub-pixel offsets, shape (S, 2): strata centres of a k x k grid (or n-rooks)."""
    return sample_offsets(int(samples), (), None)


# -- compiled kernels --------------------------------------------------------------------------

@numba.njit(inline="always", cache=True)
def _cr_weights(t):
    t2 = t * t
    t3 = t2 * t
    return (
        0.5 * (-t3 + 2.0 * t2 - t),
        0.5 * (3.0 * t3 - 5.0 * t2 + 2.0),
        0.5 * (-3.0 * t3 + 4.0 * t2 + t),
        0.5 * (t3 - t2),
    )


@numba.njit(inline="always", cache=True)
def _cr_eval(nx, ny, ca, cb, tx, ty, wrap):
    wx = _cr_weights(tx)
    wy = _cr_weights(ty)
    ref = nx[cb + 1, ca + 1]
    sx = 0.0
    sy = 0.0
    for j in range(4):
        rx = 0.0
        ry = 0.0
        for i in range(4):
            v = nx[cb + j, ca + i]
            if wrap > 0.0:
                v -= wrap * np.floor((v - ref) / wrap + 0.5)
            rx += wx[i] * v
            ry += wx[i] * ny[cb + j, ca + i]
        sx += wy[j] * rx
        sy += wy[j] * ry
    return sx, sy


@numba.njit(cache=True, nogil=True)
def _lattice_grid(nx, ny, tx, ty, wrap):
    ncy = nx.shape[0] - 3
    ncx = nx.shape[1] - 3
    ox = np.empty((ncy, ncx))
    oy = np.empty((ncy, ncx))
    for cb in range(ncy):
        for ca in range(ncx):
            ox[cb, ca], oy[cb, ca] = _cr_eval(nx, ny, ca, cb, tx, ty, wrap)
    return ox, oy


# Catmull-Rom basis: weight_i(t) = sum_a _CR[i, a] t^a
_CR = np.array([[0.0, -0.5, 1.0, -0.5], [1.0, 0.0, -2.5, 1.5], [0.0, 0.5, 2.0, -1.5], [0.0, 0.0, -0.5, 0.5]])


@numba.njit(cache=True, nogil=True)
def _cell_coefficients(nodes, state, cb0, cb1, wrap, cr_basis, coef):
    """Fill ``coef[row, ca, q]`` = CR^T P CR (``c[b, a]`` of tx^a ty^b) for the cells that interpolate:
    x and y for state 1, the direction for state 2; the x stencil unwrapped across the seam."""
    ncx = state.shape[1]
    p = np.empty((4, 4))
    t = np.empty((4, 4))
    for cb in range(cb0, cb1):
        for ca in range(ncx):
            st = state[cb, ca]
            if st <= 0:
                continue
            q0, q1 = (0, 2) if st == 1 else (2, 5)
            for q in range(q0, q1):
                ref = nodes[q, cb + 1, ca + 1]
                for j in range(4):
                    for i in range(4):
                        v = nodes[q, cb + j, ca + i]
                        if q == 0 and wrap > 0.0:
                            v -= wrap * np.floor((v - ref) / wrap + 0.5)
                        p[j, i] = v
                # t = p @ CR, then c = CR^T @ t
                for j in range(4):
                    for a in range(4):
                        acc = 0.0
                        for i in range(4):
                            acc += p[j, i] * cr_basis[i, a]
                        t[j, a] = acc
                for b in range(4):
                    for a in range(4):
                        acc = 0.0
                        for j in range(4):
                            acc += cr_basis[j, b] * t[j, a]
                        coef[cb - cb0, ca, q, b, a] = acc


@numba.njit(inline="always", cache=True)
def _poly(coef, cr, ca, q, tx, ty):
    acc = 0.0
    for b in range(3, -1, -1):
        acc = acc * ty + (((coef[cr, ca, q, b, 3] * tx + coef[cr, ca, q, b, 2]) * tx
                           + coef[cr, ca, q, b, 1]) * tx + coef[cr, ca, q, b, 0])
    return acc


@kernel
def _lattice_eval(coef, state, cb0, step, r0, offs, src_w, src_h, xs, ys, valid, need):
    h, w, n = xs.shape
    ho, wo = offs.shape[0], offs.shape[1]
    ncy, ncx = state.shape
    inv = 1.0 / step
    for r in range(h):
        ro = r % ho
        for c in range(w):
            co = c if wo > 1 else 0
            for k in range(n):
                px = (c + offs[ro, co, k, 0]) * inv
                py = (r0 + r + offs[ro, co, k, 1]) * inv
                ca = min(max(int(np.floor(px)), 0), ncx - 1)
                cb = min(max(int(np.floor(py)), 0), ncy - 1)
                st = state[cb, ca]
                tx = px - ca
                ty = py - cb
                cr = cb - cb0
                if st == 1:
                    xs[r, c, k] = _poly(coef, cr, ca, 0, tx, ty) - 0.5
                    ys[r, c, k] = _poly(coef, cr, ca, 1, tx, ty) - 0.5
                    valid[r, c, k] = True
                    need[r, c, k] = False
                elif st == 2:  # interpolated direction, projected onto the full-sphere equirect
                    dx = _poly(coef, cr, ca, 2, tx, ty)
                    dy = _poly(coef, cr, ca, 3, tx, ty)
                    dz = _poly(coef, cr, ca, 4, tx, ty)
                    phi = np.arctan2(dx, dz)
                    theta = np.arctan2(dy, np.sqrt(dx * dx + dz * dz))
                    xs[r, c, k] = (phi / np.pi + 1.0) * (0.5 * src_w) - 0.5
                    ys[r, c, k] = (1.0 - theta / (0.5 * np.pi)) * (0.5 * src_h) - 0.5
                    valid[r, c, k] = True
                    need[r, c, k] = False
                else:
                    xs[r, c, k] = 0.0
                    ys[r, c, k] = 0.0
                    valid[r, c, k] = False
                    need[r, c, k] = st == 0


@numba.njit(cache=True, nogil=True)
def _lattice_rows(coef, state, cb0, inv, r0, offs, src_w, src_h, xs, ys, valid, need):
    """:func:`_lattice_eval` for offsets shared by every pixel: along a row of samples ty is fixed, so
    each cell's bicubic collapses to a cubic in tx (``rc``), made once per cell and row."""
    h, w, n = xs.shape
    ncy, ncx = state.shape
    rc = np.empty((5, 4))
    for r in range(h):
        for k in range(n):
            py = (r0 + r + offs[0, 0, k, 1]) * inv
            cb = min(max(int(np.floor(py)), 0), ncy - 1)
            ty = py - cb
            cr = cb - cb0
            cur = -1
            st = 0
            for c in range(w):
                px = (c + offs[0, 0, k, 0]) * inv
                ca = min(max(int(np.floor(px)), 0), ncx - 1)
                if ca != cur:
                    cur = ca
                    st = state[cb, ca]
                    if st > 0:
                        q0, q1 = (0, 2) if st == 1 else (2, 5)
                        for q in range(q0, q1):
                            for a in range(4):
                                rc[q, a] = ((coef[cr, ca, q, 3, a] * ty + coef[cr, ca, q, 2, a]) * ty
                                            + coef[cr, ca, q, 1, a]) * ty + coef[cr, ca, q, 0, a]
                tx = px - ca
                if st == 1:
                    xs[r, c, k] = ((rc[0, 3] * tx + rc[0, 2]) * tx + rc[0, 1]) * tx + rc[0, 0] - 0.5
                    ys[r, c, k] = ((rc[1, 3] * tx + rc[1, 2]) * tx + rc[1, 1]) * tx + rc[1, 0] - 0.5
                    valid[r, c, k] = True
                    need[r, c, k] = False
                elif st == 2:  # interpolated direction, projected onto the full-sphere equirect
                    dx = ((rc[2, 3] * tx + rc[2, 2]) * tx + rc[2, 1]) * tx + rc[2, 0]
                    dy = ((rc[3, 3] * tx + rc[3, 2]) * tx + rc[3, 1]) * tx + rc[3, 0]
                    dz = ((rc[4, 3] * tx + rc[4, 2]) * tx + rc[4, 1]) * tx + rc[4, 0]
                    phi = np.arctan2(dx, dz)
                    theta = np.arctan2(dy, np.sqrt(dx * dx + dz * dz))
                    xs[r, c, k] = (phi / np.pi + 1.0) * (0.5 * src_w) - 0.5
                    ys[r, c, k] = (1.0 - theta / (0.5 * np.pi)) * (0.5 * src_h) - 0.5
                    valid[r, c, k] = True
                    need[r, c, k] = False
                else:
                    xs[r, c, k] = 0.0
                    ys[r, c, k] = 0.0
                    valid[r, c, k] = False
                    need[r, c, k] = st == 0


def _sphere_project(d: np.ndarray, width: int, height: int):
    """Full-sphere equirect pixel coordinates of (not necessarily unit) directions (the lens's formulas)."""
    phi = np.arctan2(d[..., 0], d[..., 2])
    theta = np.arctan2(d[..., 1], np.hypot(d[..., 0], d[..., 2]))
    return (phi / np.pi + 1.0) * (0.5 * width), (1.0 - theta / (np.pi / 2)) * (0.5 * height)
