"""NumPy references of the compiled warp kernels (:mod:`lenslab.warp.kernels.native`), for the tests.

Each function computes what its C++ kernel computes, in the same order and the same precision (float32
lerps for bilinear, float64 weights for the footprint filter), one readable step at a time; the tests
hold the kernels to them. They are slow (the footprint reference is a Python loop): tests only.
"""

from __future__ import annotations

import math

import numpy as np

from lenslab.warp.pyramid import MAX_TAPS, THIN, WINDOW, Pyramid
from lenslab.warp.seam import fold_taps as fold_index

INVALID = np.uint32(0xFFFFFFFF)
FOLDED = np.uint32(0xFFFFFFFE)
FAR = np.float32(2.0**40)  # a position beyond +-2^40 (inf included) is read at +-2^40, NaN at -2^40 (clamp_pos)


def clamp_pos(v):
    """Map positions as the samplers read them (``clamp_pos`` in ``src/native/kernels.h``): an edge pixel for
    1e30, inf or NaN, and no float converted to an integer out of range."""
    v = np.asarray(v, dtype=np.float32)
    return np.where(v >= -FAR, np.minimum(v, FAR), -FAR).astype(np.float32)


def _taps(src, x, y, border):
    """The four taps' values (n, C) float32 and the fractions (float32) at index coordinates ``x, y``."""
    sh, sw = src.shape[:2]
    x, y = clamp_pos(x), clamp_pos(y)
    fx0, fy0 = np.floor(x), np.floor(y)
    i0, j0 = fx0.astype(np.int64), fy0.astype(np.int64)
    vals = []
    for di, dj in ((0, 0), (1, 0), (0, 1), (1, 1)):
        i, j = fold_index(i0 + di, j0 + dj, sw, sh, *border)
        vals.append(src[j, i])
    return vals, (x - fx0)[:, None], (y - fy0)[:, None]


def bilinear1(src: np.ndarray, xs: np.ndarray, ys: np.ndarray, valid: np.ndarray, border):
    """One sample per pixel: ``(out (n, C), alpha (n,))``; float32 lerps ``a + t (b - a)``, along x first. A
    value those steps make non-finite (taps of opposite signs beyond 1.7e38: ``b - a`` overflows) is made
    again as the float64 weighted sum of the taps of non-zero weight (:func:`lerp_wide`)."""
    x, y, v = (np.asarray(a).reshape(-1) for a in (xs, ys, valid))
    x, y = x.astype(np.float32), y.astype(np.float32)
    (a, b, c, d), tx, ty = _taps(src, x, y, border)
    with np.errstate(over="ignore", invalid="ignore"):
        upper = a + tx * (b - a)
        lower = c + tx * (d - c)
        out = (upper + ty * (lower - upper)).astype(np.float32)
    bad = ~np.isfinite(out)
    if bad.any():
        tx2, ty2 = np.broadcast_to(tx, out.shape)[bad], np.broadcast_to(ty, out.shape)[bad]
        out[bad] = lerp_wide(a[bad], b[bad], c[bad], d[bad], tx2, ty2)
    out[~v] = 0.0
    return out, v.astype(np.float32)


def lerp_wide(a, b, c, d, tx, ty) -> np.ndarray:
    """The bilinear value of taps ``a b`` (upper row) ``c d`` at fractions ``tx, ty`` as the float64 sum of the
    taps times their weights, a tap of weight 0 left out (an inf tap of weight 0 is not read): finite for
    finite taps of any size, float32 out."""
    wx, wy = np.asarray(tx, np.float64), np.asarray(ty, np.float64)
    ux, uy = 1.0 - wx, 1.0 - wy
    s = np.zeros(np.shape(a), np.float64)
    with np.errstate(invalid="ignore"):
        for w, t in ((ux * uy, a), (wx * uy, b), (ux * wy, c), (wx * wy, d)):
            s += np.where(w != 0.0, w * np.asarray(t, np.float64), 0.0)
    return s.astype(np.float32)


def bilinear_n(src, xs, ys, valid, border):
    """``n`` samples per pixel (``xs`` (..., n)): the sum of the valid samples' bilinear values (float32
    weights ``(1 - tx)(1 - ty)`` etc.) divided by ``n``, and the fraction valid."""
    ns = xs.shape[-1]
    x, y, v = (np.asarray(a).reshape(-1, ns) for a in (xs, ys, valid))
    (a, b, c, d), tx, ty = _taps(src, x.reshape(-1).astype(np.float32), y.reshape(-1).astype(np.float32), border)
    one = np.float32(1.0)
    w = [((one - tx) * (one - ty)), (tx * (one - ty)), ((one - tx) * ty), (tx * ty)]  # float32 weights
    f64 = [np.asarray(t, np.float64) for t in (a, b, c, d)]
    val = w[0].astype(np.float64) * f64[0] + w[1].astype(np.float64) * f64[1] + w[2].astype(np.float64) * f64[2] \
        + w[3].astype(np.float64) * f64[3]  # float64 sums: opposite signs near float32's largest do not overflow
    val = np.where(v.reshape(-1, 1), val, 0.0).reshape(x.shape + (src.shape[2],))
    acc = np.zeros((x.shape[0], src.shape[2]), np.float64)
    for k in range(ns):  # in sample order, as the kernel adds them
        acc += val[:, k]
    inv = np.float32(1.0 / ns)
    big = float(np.finfo(np.float32).max)  # the mean of finite values is in range up to a float64 rounding
    mean = np.clip(acc * np.float64(inv), -big, big).astype(np.float32)
    return mean, (v.sum(axis=1) * np.float64(inv)).astype(np.float32)


def taps(src, xs, ys, valid):
    """The cached taps of one-sample map positions: ``(off uint32, tx, ty)``, ``off`` the flat index of the
    top-left tap, INVALID without a source, FOLDED where a tap leaves the image (fractions 0 there)."""
    sh, sw = src.shape[:2]
    x, y, v = (np.asarray(a).reshape(-1) for a in (xs, ys, valid))
    x, y = clamp_pos(x), clamp_pos(y)
    fx0, fy0 = np.floor(x), np.floor(y)
    i0, j0 = fx0.astype(np.int64), fy0.astype(np.int64)
    inside = v & (i0 >= 0) & (j0 >= 0) & (i0 + 1 < sw) & (j0 + 1 < sh)
    off = np.where(v, FOLDED, INVALID).astype(np.uint32)
    off[inside] = (j0 * sw + i0)[inside].astype(np.uint32)
    tx = np.where(inside, x - fx0, 0).astype(np.float32)
    ty = np.where(inside, y - fy0, 0).astype(np.float32)
    return off, tx, ty


def _tent_c(u: float) -> float:
    """The tent's antiderivative: 0 below -1, 1 above 1."""
    v = min(1.0, max(-1.0, u))
    return 0.5 + v - 0.5 * v * abs(v)


G2 = 0.5 / math.sqrt(3.0)  # the 2-point Gauss-Legendre nodes at mid -+ G2 * len


def slice_weights(cx, cy, ax, ay, bx, by, wx0, wy0, nwx, nwy):
    """``(weights (nwy, nwx) float64, area)``: texel (wx0 + i, wy0 + j)'s weight in the bilinear
    reconstruction integrated over the parallelogram ``c + s a + r b`` (s, r in [-1/2, 1/2]).

    Between consecutive breakpoints in y (the vertices and the texel rows) the slice's ends move
    linearly and each texel's weight is a cubic in y: 2-point Gauss-Legendre; across x each slice is
    integrated exactly by the tent's antiderivative, and split between the two texel rows around it by
    the linear interpolation of the bilinear reconstruction.
    """
    vx = [cx - 0.5 * ax - 0.5 * bx, cx + 0.5 * ax - 0.5 * bx, cx + 0.5 * ax + 0.5 * bx, cx - 0.5 * ax + 0.5 * bx]
    vy = [cy - 0.5 * ay - 0.5 * by, cy + 0.5 * ay - 0.5 * by, cy + 0.5 * ay + 0.5 * by, cy - 0.5 * ay + 0.5 * by]
    edges = []
    for e in range(4):
        f = (e + 1) % 4
        if vy[e] <= vy[f]:
            lo, xlo, hi, xhi = vy[e], vx[e], vy[f], vx[f]
        else:
            lo, xlo, hi, xhi = vy[f], vx[f], vy[e], vx[e]
        edges.append((lo, hi, xlo, (xhi - xlo) / (hi - lo) if hi > lo else 0.0))
    ys = sorted(vy)
    w = np.zeros((nwy + 2, nwx))  # rows -1 and nwy: scratch
    # only the window's rows -1 .. nwy - 1 (a footprint inside its window lies within them; a clipped one takes
    # its sum from the weights)
    y_end = min(ys[3], float(wy0 + nwy))
    total, y, v, seen, left, right = 0.0, max(ys[0], float(wy0 - 1)), 1, 0, edges[0], edges[0]
    while y < y_end:
        while v < 3 and ys[v] <= y:
            v += 1
        if v != seen:  # a new pair of vertices: the edges on the left and on the right until the next
            seen = v
            ym = 0.5 * (ys[v - 1] + ys[v])
            active = [(xlo + (ym - lo) * k, e) for e, (lo, hi, xlo, k) in enumerate(edges)
                      if lo <= ym <= hi and hi != lo]
            left = edges[min(active, key=lambda t: t[0])[1]] if active else edges[0]  # the first of equals
            right = edges[max(active, key=lambda t: t[0])[1]] if active else edges[0]
        y1 = min(ys[v], math.floor(y) + 1.0)
        length, mid = y1 - y, 0.5 * (y + y1)
        g = 0.5 * length
        pts = []
        for yy in (mid - G2 * length, mid + G2 * length):
            xl = left[2] + (yy - left[0]) * left[3]
            xr = max(xl, right[2] + (yy - right[0]) * right[3])
            total += g * (xr - xl)
            ty = yy - math.floor(mid)
            pts.append((xl, xr, g * (1.0 - ty), g * ty))
        j = math.floor(mid) - wy0
        if not -1 <= j < nwy:
            y = y1
            continue
        (xl0, xr0, a0, b0), (xl1, xr1, a1, b1) = pts
        lo_x, hi_x = min(xl0, xl1), max(xr0, xr1)
        for i in range(max(math.floor(lo_x - 1.0) + 1 - wx0, 0), min(math.floor(hi_x + 1.0) + 1 - wx0, nwx)):
            wa = _tent_c(xr0 - wx0 - i) - _tent_c(xl0 - wx0 - i)
            wb = _tent_c(xr1 - wx0 - i) - _tent_c(xl1 - wx0 - i)
            w[j + 1, i] += a0 * wa + a1 * wb
            w[j + 2, i] += b0 * wa + b1 * wb
        y = y1
    return w[1:-1], total


def window_rows(win: np.ndarray):
    """``(f, h, s)`` of a window's rows (``win`` (rows, texels, C) float64, the slices' rows first): the texels'
    values, half the step to the next texel, and the integral of the row's linear interpolant from texel 0 to
    each texel (trapezoids summed in order), so that the integral from texel 0 to ``u + t`` is ``s + t (f + t h)``."""
    f = np.asarray(win, dtype=np.float64)
    h = np.zeros_like(f)
    s = np.zeros_like(f)
    h[:, :-1] = 0.5 * (f[:, 1:] - f[:, :-1])
    for u in range(f.shape[1] - 2):
        s[:, u + 1] = s[:, u] + 0.5 * (f[:, u] + f[:, u + 1])
    return f, h, s


def edge_integral(xa, ya, xb, yb, sign, rows, acc):
    """``acc + sign *`` the integral over y of ``F(x(y), y)`` along the edge from ``(xa, ya)`` to ``(xb, yb)``
    (``ya <= yb``, window coordinates), ``F(x, y)`` the integral of the bilinear reconstruction along row y from
    the window's first texel to x. Cut at the texel rows, each piece by 2-point Gauss-Legendre."""
    if not yb > ya:
        return acc
    f, h, s = rows
    k = (xb - xa) / (yb - ya)
    umax, jmax = float(f.shape[1] - 2), f.shape[0] - 2
    n = math.floor(ya)
    while n < yb:
        y0, y1 = max(ya, n), min(yb, n + 1.0)
        length, mid = y1 - y0, 0.5 * (y0 + y1)
        g = sign * 0.5 * length
        j = min(jmax, max(0, int(n)))
        for yy in (mid - G2 * length, mid + G2 * length):
            x = xa + (yy - ya) * k
            uf = min(umax, max(0.0, math.floor(x)))
            t, ty, u = x - uf, yy - n, int(uf)
            f0 = s[j, u] + t * (f[j, u] + t * h[j, u])
            f1 = s[j + 1, u] + t * (f[j + 1, u] + t * h[j + 1, u])
            acc = acc + (g * (1.0 - ty)) * f0 + (g * ty) * f1
        n += 1.0
    return acc


def prefix_slices(cx, cy, ax, ay, bx, by, rows):
    """``(integral (C,), area)``: the bilinear reconstruction of a window's rows (:func:`window_rows`) integrated
    over the parallelogram ``c + s a + r b`` (s, r in [-1/2, 1/2]; window coordinates, texel (0, 0) the window's
    first). By Green's theorem: the integral over y of F at the right ends of its rows less F at the left ends,
    edge by edge (:func:`edge_integral`); the area is ``|a x b|``."""
    vx = [cx - 0.5 * ax - 0.5 * bx, cx + 0.5 * ax - 0.5 * bx, cx + 0.5 * ax + 0.5 * bx, cx - 0.5 * ax + 0.5 * bx]
    vy = [cy - 0.5 * ay - 0.5 * by, cy + 0.5 * ay - 0.5 * by, cy + 0.5 * ay + 0.5 * by, cy - 0.5 * ay + 0.5 * by]
    ib = 0
    for e in range(1, 4):  # the lowest vertex (the first of equals); the highest is opposite
        ib = e if vy[e] < vy[ib] else ib
    it, m1, m2 = (ib + 2) % 4, (ib + 1) % 4, (ib + 3) % 4
    cross = (vx[m1] - vx[ib]) * (vy[it] - vy[ib]) - (vy[m1] - vy[ib]) * (vx[it] - vx[ib])
    left, right = (m1, m2) if cross < 0.0 else (m2, m1)  # left of the line from the lowest to the highest
    acc = np.zeros(rows[0].shape[2])
    for a, b, sign in ((ib, right, 1.0), (right, it, 1.0), (ib, left, -1.0), (left, it, -1.0)):
        acc = edge_integral(vx[a], vy[a], vx[b], vy[b], sign, rows, acc)
    return acc, abs(ax * by - ay * bx)


def level_rows(shapes, ys, valid, foot) -> np.ndarray:
    """``(levels, 2)`` int64: the rows ``[first, end)`` of each pyramid level that the footprint filter reads for
    the valid samples at rows ``ys`` with sides ``foot`` (..., 4): each sample's level and window as
    :func:`footprint` picks them, a texel wider each way (level 0 and levels no sample picks: first > end)."""
    shapes = np.asarray(shapes)
    rows = np.array([[np.iinfo(np.int64).max, np.iinfo(np.int64).min]] * len(shapes), np.int64)
    f = np.asarray(foot, np.float32).reshape(-1, 4)
    f = np.where(np.isnan(f), 0.0, clamp_pos(f)).astype(np.float64)
    y = clamp_pos(np.asarray(ys, np.float32).reshape(-1)).astype(np.float64)
    ok = np.asarray(valid, bool).reshape(-1)
    longest = np.maximum(np.sqrt(f[:, 0] ** 2 + f[:, 1] ** 2), np.sqrt(f[:, 2] ** 2 + f[:, 3] ** 2))
    lev = np.zeros(len(y), np.int64)
    for k in range(1, len(shapes)):
        lev += longest > MAX_TAPS * (1 << (k - 1))
    for k in range(1, len(shapes)):
        sel = ok & (lev == k)
        if not sel.any():
            continue
        lh = int(shapes[k][0])
        scale = lh / float(shapes[0][0])
        ey = np.minimum(0.5 * (np.abs(f[sel, 1]) + np.abs(f[sel, 3])) * scale + 1.0, WINDOW // 2 + 1.0)
        cy = (y[sel] + 0.5) * scale - 0.5
        rows[k] = (max(-lh, int(np.floor(cy - ey).min()) - 1), min(2 * lh, int(np.floor(cy + ey).max()) + 2))
    return rows


def footprint(pyr: Pyramid, xs, ys, valid, foot, border):
    """The footprint filter (see :mod:`lenslab.warp.antialias`): ``(out (n, C), alpha (n,))`` for pixels of
    ``S`` samples (``xs`` (..., S), ``foot`` (..., S, 4)), every step in float64 Python arithmetic."""
    ns = xs.shape[-1]
    x, y, v = (np.asarray(a).reshape(-1, ns) for a in (xs, ys, valid))
    f = np.asarray(foot, dtype=np.float64).reshape(-1, ns, 4)
    nc = pyr.channels
    levels = [pyr.source] + [pyr.rest[o:o + h * w * nc].reshape(h, w, nc)
                             for o, (h, w) in zip(pyr.offsets[1:], pyr.shapes[1:])]
    h0 = float(pyr.shapes[0, 0])
    out = np.zeros((x.shape[0], nc))
    alpha = np.zeros(x.shape[0])
    for q in range(x.shape[0]):
        acc = np.zeros(nc)
        hits = 0
        for s in range(ns):
            if not v[q, s]:
                continue
            hits += 1
            ax, ay, bx, by = (0.0 if math.isnan(t) else float(clamp_pos(t)) for t in f[q, s])  # NaN: a point
            longest = max(math.sqrt(ax * ax + ay * ay), math.sqrt(bx * bx + by * by))
            lev = 0
            while lev + 1 < len(levels) and longest > MAX_TAPS * (1 << lev):
                lev += 1
            img = levels[lev]
            lh, lw = img.shape[:2]
            scale = lh / h0
            ax, ay, bx, by = ax * scale, ay * scale, bx * scale, by * scale
            cx = (float(clamp_pos(x[q, s])) + 0.5) * scale - 0.5
            cy = (float(clamp_pos(y[q, s])) + 0.5) * scale - 0.5
            if abs(ax * by - ay * bx) < THIN * THIN:  # a line or a point: a thickness far below a texel
                la, lb = math.hypot(ax, ay), math.hypot(bx, by)
                if la >= lb and la > 0.0:
                    bx, by = -THIN * ay / la, THIN * ax / la
                elif lb > 0.0:
                    ax, ay = THIN * by / lb, -THIN * bx / lb
                else:
                    ax, ay, bx, by = THIN, 0.0, 0.0, THIN
            # the window: every texel the thickened footprint touches
            ex, ey = 0.5 * (abs(ax) + abs(bx)) + 1.0, 0.5 * (abs(ay) + abs(by)) + 1.0
            wx0, wy0 = math.floor(cx - ex) + 1, math.floor(cy - ey) + 1
            nwx, nwy = math.floor(cx + ex) + 1 - wx0, math.floor(cy + ey) + 1 - wy0
            if nwx > WINDOW:  # a footprint beyond the coarsest level: the window centred on it
                wx0, nwx = math.floor(cx) + 1 - WINDOW // 2, WINDOW
            if nwy > WINDOW:
                wy0, nwy = math.floor(cy) + 1 - WINDOW // 2, WINDOW
            jj, ii = np.mgrid[wy0:wy0 + nwy, wx0:wx0 + nwx]
            fi, fj = fold_index(ii.ravel(), jj.ravel(), lw, lh, *border)
            texels = img[fj, fi].astype(np.float64)
            if nwx < WINDOW and nwy < WINDOW:  # inside its window: the rows' prefix sums
                win = texels.reshape(nwy, nwx, nc)
                if ey > ex:  # sliced along the shorter extent: here x, so x and y swap roles
                    part, area = prefix_slices(cy - wy0, cx - wx0, ay, ax, by, bx, window_rows(win.transpose(1, 0, 2)))
                else:
                    part, area = prefix_slices(cx - wx0, cy - wy0, ax, ay, bx, by, window_rows(win))
                acc += part * (1.0 / area)
                continue
            # clipped by its window (beyond the coarsest level): the texels' weights
            if ey > ex:
                wt, area = slice_weights(cy, cx, ay, ax, by, bx, wy0, wx0, nwy, nwx)
                wt = wt.T
            else:
                wt, area = slice_weights(cx, cy, ax, ay, bx, by, wx0, wy0, nwx, nwy)
            area = float(wt.sum())
            acc += (wt.ravel()[:, None] * texels).sum(axis=0) * (1.0 / area)
        out[q] = acc / ns
        alpha[q] = hits / ns
    return out.astype(np.float32), alpha.astype(np.float32)


def neighbour_secants(xs, ys, vs, top: int, h: int, wrap: float, piece=None):
    """Footprint sides of rows ``top:top + h`` of a one-sample map (``xs, ys`` float32 and ``vs`` bool, (rows,
    W)) from the neighbours' positions: ``(foot (h, W, 4), edge (h, W))``.

    Along each axis: the central difference halved where both neighbours are valid, else the one-sided
    difference to a valid neighbour (the pixel itself valid), else 0. A neighbour counts only inside the
    image and in the pixel's piece (``piece``: (rows, W) piece numbers; None: one piece). x differences, float32
    differences of float32 positions, are unwrapped by the period ``wrap`` before halving. ``edge``: a
    neighbour that counts has the other validity.
    """
    nrows, w = xs.shape
    rr = np.arange(top, top + h)[:, None] + np.zeros((1, w), np.int64)
    cc = np.arange(w)[None, :] + np.zeros((h, 1), np.int64)
    foot = np.zeros((h, w, 4))
    edge = np.zeros((h, w), bool)
    v0 = vs[rr, cc]

    piece = np.zeros((nrows, w), np.int32) if piece is None else piece

    for axis in range(2):
        if axis == 0:
            lo, hi = (rr, np.maximum(cc - 1, 0)), (rr, np.minimum(cc + 1, w - 1))
            lo_ok, hi_ok = cc > 0, cc + 1 < w
        else:
            lo, hi = (np.maximum(rr - 1, 0), cc), (np.minimum(rr + 1, nrows - 1), cc)
            lo_ok, hi_ok = rr > 0, rr + 1 < nrows
        lo_ok = lo_ok & (piece[lo] == piece[rr, cc])
        hi_ok = hi_ok & (piece[hi] == piece[rr, cc])
        vl, vh = lo_ok & vs[lo], hi_ok & vs[hi]
        edge |= (lo_ok & (vs[lo] != v0)) | (hi_ok & (vs[hi] != v0))
        both, up, down = vl & vh, ~(vl & vh) & vh & v0, ~(vl & vh) & ~(vh & v0) & vl & v0
        me = (rr, cc)
        for k, arr in ((0, xs), (1, ys)):
            d = np.zeros((h, w))
            d[both] = (arr[hi] - arr[lo])[both].astype(np.float64)
            d[up] = (arr[hi] - arr[me])[up].astype(np.float64)
            d[down] = (arr[me] - arr[lo])[down].astype(np.float64)
            if k == 0 and wrap > 0.0:
                d = d - wrap * np.floor(d / wrap + 0.5)
            foot[..., 2 * axis + k] = np.where(both, 0.5, 1.0) * d
    return foot.astype(np.float32), edge


def secants(xs, ys, vs, wrap: float):
    """Footprint sides ``(h, W, S, 4)`` float32 of supersampled pixels from the map ``xs, ys`` (float32) and
    ``vs`` (bool), all (h, W, 5, S): at each sample (index 0) and the ends of its secants along x (1, 2) and y
    (3, 4). Each side is the end-to-end difference (float32) where both ends are valid, else twice the
    difference between the sample and its valid end (the sample valid), else 0; x is unwrapped by ``wrap``."""
    h, w, _, n = xs.shape
    foot = np.zeros((h, w, n, 4))
    for axis in range(2):
        lo, hi = 1 + 2 * axis, 2 + 2 * axis
        vl, vh, v0 = vs[:, :, lo], vs[:, :, hi], vs[:, :, 0]
        both = vl & vh
        up = ~both & vh & v0
        down = ~both & ~up & vl & v0
        for k, arr in ((0, xs), (1, ys)):
            d = np.zeros((h, w, n))
            d[both] = (arr[:, :, hi] - arr[:, :, lo])[both].astype(np.float64)
            d[up] = 2.0 * (arr[:, :, hi] - arr[:, :, 0])[up].astype(np.float64)
            d[down] = 2.0 * (arr[:, :, 0] - arr[:, :, lo])[down].astype(np.float64)
            if k == 0 and wrap > 0.0:
                d = d - wrap * np.floor(d / wrap + 0.5)
            foot[..., 2 * axis + k] = d
    return foot.astype(np.float32)

