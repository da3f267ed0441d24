"""NumPy references of the compiled warp kernels (:mod:`lenslab.warp.kernels.native`), for the tests.

Each function computes what its C++ kernel computes, in the same order and the same precision (float32
lerps for bilinear, float64 weights for the footprint filter), one readable step at a time; the tests
hold the kernels to them. They are slow (the footprint reference is a Python loop): tests only.
"""

from __future__ import annotations

import math

import numpy as np

from lenslab.warp.pyramid import AXIS_TOL, DENSITY, MAX_TAPS, Pyramid
from lenslab.warp.seam import fold_taps as fold_index

INVALID = np.uint32(0xFFFFFFFF)
FOLDED = np.uint32(0xFFFFFFFE)


def _taps(src, x, y, border):
    """The four taps' values (n, C) float32 and the fractions (float32) at index coordinates ``x, y``."""
    sh, sw = src.shape[:2]
    fx0, fy0 = np.floor(x), np.floor(y)
    i0, j0 = fx0.astype(np.int64), fy0.astype(np.int64)
    vals = []
    for di, dj in ((0, 0), (1, 0), (0, 1), (1, 1)):
        i, j = fold_index(i0 + di, j0 + dj, sw, sh, *border)
        vals.append(src[j, i])
    return vals, (x - fx0)[:, None], (y - fy0)[:, None]


def bilinear1(src: np.ndarray, xs: np.ndarray, ys: np.ndarray, valid: np.ndarray, border):
    """One sample per pixel: ``(out (n, C), alpha (n,))``; float32 lerps ``a + t (b - a)``, along x first."""
    x, y, v = (np.asarray(a).reshape(-1) for a in (xs, ys, valid))
    x, y = x.astype(np.float32), y.astype(np.float32)
    (a, b, c, d), tx, ty = _taps(src, x, y, border)
    upper = a + tx * (b - a)
    lower = c + tx * (d - c)
    out = (upper + ty * (lower - upper)).astype(np.float32)
    out[~v] = 0.0
    return out, v.astype(np.float32)


def bilinear_n(src, xs, ys, valid, border):
    """``n`` samples per pixel (``xs`` (..., n)): the sum of the valid samples' bilinear values (float32
    weights ``(1 - tx)(1 - ty)`` etc.) divided by ``n``, and the fraction valid."""
    ns = xs.shape[-1]
    x, y, v = (np.asarray(a).reshape(-1, ns) for a in (xs, ys, valid))
    (a, b, c, d), tx, ty = _taps(src, x.reshape(-1).astype(np.float32), y.reshape(-1).astype(np.float32), border)
    one = np.float32(1.0)
    val = ((one - tx) * (one - ty)) * a + (tx * (one - ty)) * b + ((one - tx) * ty) * c + (tx * ty) * d
    val = np.where(v.reshape(-1, 1), val, np.float32(0.0)).reshape(x.shape + (src.shape[2],))
    acc = np.zeros((x.shape[0], src.shape[2]), np.float32)
    for k in range(ns):  # in sample order, as the kernel adds them
        acc += val[:, k]
    inv = np.float32(1.0 / ns)
    big = np.finfo(np.float32).max  # a sum near the largest float32 may pass it; the mean of finite values may not
    with np.errstate(over="ignore"):
        mean = acc * inv
    return np.where(mean > big, big, np.where(mean < -big, -big, mean)), (v.sum(axis=1) * np.float64(inv)).astype(np.float32)


def taps(src, xs, ys, valid):
    """The cached taps of one-sample map positions: ``(off uint32, tx, ty)``, ``off`` the flat index of the
    top-left tap, INVALID without a source, FOLDED where a tap leaves the image (fractions 0 there)."""
    sh, sw = src.shape[:2]
    x, y, v = (np.asarray(a).reshape(-1) for a in (xs, ys, valid))
    fx0, fy0 = np.floor(x), np.floor(y)
    i0, j0 = fx0.astype(np.int64), fy0.astype(np.int64)
    inside = v & (i0 >= 0) & (j0 >= 0) & (i0 + 1 < sw) & (j0 + 1 < sh)
    off = np.where(v, FOLDED, INVALID).astype(np.uint32)
    off[inside] = (j0 * sw + i0)[inside].astype(np.uint32)
    tx = np.where(inside, x - fx0, 0).astype(np.float32)
    ty = np.where(inside, y - fy0, 0).astype(np.float32)
    return off, tx, ty


def _tent_box_weights(x: float, width: float, i0: int, n: int) -> list[float]:
    """Weights of texels ``i0..i0+n-1``: the tent averaged over a box of ``width`` centred at ``x``."""
    if width < 1e-6:
        return [max(0.0, 1.0 - abs(x - (i0 + i))) for i in range(n)]

    def cdf(u):
        v = min(1.0, max(-1.0, u))
        return 0.5 + v - 0.5 * v * abs(v)

    hw = 0.5 * width
    return [(cdf(x - (i0 + i) + hw) - cdf(x - (i0 + i) - hw)) * (1.0 / width) for i in range(n)]


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
            ax, ay, bx, by = (float(t) for t in f[q, s])
            la, lb = math.sqrt(ax * ax + ay * ay), math.sqrt(bx * bx + by * by)
            lev = 0
            while lev + 1 < len(levels) and max(la, lb) > MAX_TAPS * (1 << lev):
                lev += 1
            img = levels[lev]
            lh, lw = img.shape[:2]
            scale = lh / h0
            sxx = (ax * ax + bx * bx) * scale * scale
            syy = (ay * ay + by * by) * scale * scale
            sxy = (ax * ay + bx * by) * scale * scale
            cx = (float(x[q, s]) + 0.5) * scale - 0.5
            cy = (float(y[q, s]) + 0.5) * scale - 0.5
            if sxx <= 9.0 and syy <= 9.0 and abs(sxy) <= AXIS_TOL:
                na = nb = 1
                cells = [(cx, cy)]
                bw, bh = math.sqrt(sxx), math.sqrt(syy)
            else:
                na = max(1, math.ceil(la * scale * DENSITY))
                nb = max(1, math.ceil(lb * scale * DENSITY))
                bw = scale * math.sqrt((ax / na) ** 2 + (bx / nb) ** 2)
                bh = scale * math.sqrt((ay / na) ** 2 + (by / nb) ** 2)
                cells = []
                for c in range(na * nb):
                    fa = (c % na + 0.5) / na - 0.5
                    fb = (c // na + 0.5) / nb - 0.5
                    cells.append((cx + (fa * ax + fb * bx) * scale, cy + (fa * ay + fb * by) * scale))
            bw, bh = min(3.0, bw), min(3.0, bh)
            # every cell: the tent averaged over a bw x bh box, its weights normalised to sum to 1/cells
            wsum = {}
            for px, py in cells:
                i0 = math.floor(px - 1.0 - 0.5 * bw) + 1
                j0 = math.floor(py - 1.0 - 0.5 * bh) + 1
                ni = math.floor(px + 1.0 + 0.5 * bw) + 1 - i0
                nj = math.floor(py + 1.0 + 0.5 * bh) + 1 - j0
                kx = _tent_box_weights(px, bw, i0, ni)
                ky = _tent_box_weights(py, bh, j0, nj)
                norm = (1.0 / len(cells)) / (sum(kx) * sum(ky))
                for j in range(nj):
                    for i in range(ni):
                        wsum[(i0 + i, j0 + j)] = wsum.get((i0 + i, j0 + j), 0.0) + kx[i] * (ky[j] * norm)
            for (i, j), w in wsum.items():
                if w != 0.0:
                    fi, fj = fold_index([i], [j], lw, lh, *border)
                    acc += w * img[fj[0], fi[0]].astype(np.float64)
        out[q] = acc / ns
        alpha[q] = hits / ns
    return out.astype(np.float32), alpha.astype(np.float32)


def edges(src, idx, exs, eys, evalid, ns: int, border, out, alpha) -> None:
    """Adds the split edge samples into ``out`` (n, C) and ``alpha`` (n,): each sample's valid sub-samples,
    read bilinearly in float64, sum to their share ``1 / (K ns)`` of the pixel."""
    for e, q in enumerate(np.asarray(idx) // ns):
        ok = np.asarray(evalid[e], bool)
        x = np.asarray(exs[e], np.float64)[ok]
        y = np.asarray(eys[e], np.float64)[ok]
        fx0, fy0 = np.floor(x), np.floor(y)
        tx, ty = x - fx0, y - fy0
        acc = np.zeros(src.shape[2])
        for di, dj, w in ((0, 0, (1 - tx) * (1 - ty)), (1, 0, tx * (1 - ty)), (0, 1, (1 - tx) * ty), (1, 1, tx * ty)):
            i, j = fold_index(fx0.astype(np.int64) + di, fy0.astype(np.int64) + dj, src.shape[1], src.shape[0],
                              *border)
            acc += (w[:, None] * src[j, i].astype(np.float64)).sum(axis=0)
        scale = 1.0 / (exs.shape[1] * ns)
        out[q] = (out[q].astype(np.float64) + acc * scale).astype(np.float32)
        alpha[q] = np.float32(np.float64(alpha[q]) + ok.sum() * scale)




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
