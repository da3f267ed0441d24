"""NumPy references of the compiled warp kernels (:mod:`lenslab.warp.kernels.native`), for the tests.

Each function computes what its C++ kernel computes, in the same order and the same precision (float32
lerps for bilinear, float64 weights for the footprint filter), one readable step at a time; the tests
hold the kernels to them. They are slow (the footprint reference is a Python loop): tests only.
"""

from __future__ import annotations

import numpy as np

from lenslab.warp.kernels.footprint_reference import (  # noqa: F401  (the footprint filter's reference)
    edge_integral, footprint, prefix_slices, slice_weights, window_rows)
from lenslab.warp.kernels.positions import FAR, clamp_pos  # noqa: F401  (read as reference.clamp_pos too)
from lenslab.warp.pyramid import MAX_TAPS, WINDOW
from lenslab.warp.seam import fold_taps as fold_index

INVALID = np.uint32(0xFFFFFFFF)
FOLDED = np.uint32(0xFFFFFFFE)


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

