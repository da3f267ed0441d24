"""The footprint prefilter's source side: a box-filtered pyramid of the source and the compiled
sampler that averages it over each output sample's footprint (see :mod:`lenslab.warp.antialias` for
the method and the footprints themselves)."""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np

from lenslab.warp.dispatch import kernel
from lenslab.warp.filters import F32_MAX
from lenslab.warp.seam import Border, fold_index

MAX_TAPS = 8.0  # longest side of a footprint, in texels of the level it is read from
AXIS_TOL = 0.125  # texels^2: a footprint whose x-y covariance (times 12) is below this is one box
DENSITY = 0.75  # cells per texel along each side of the footprint (measured best accuracy per cost)
U1, U2 = np.uint64(1), np.uint64(2)  # channel offsets: texel offsets are unsigned (no negative-index test per read)
WINDOW = 16  # texels: the side of the window of weights a footprint is gathered through (fits MAX_TAPS + 5)


@dataclass
class Pyramid:
    """Box-filtered levels of a source: level 0 is the source itself, the others packed in one buffer."""

    level0: np.ndarray  # the source, flattened (a view, no copy)
    rest: np.ndarray  # levels 1.. one after the other, flattened float32
    shapes: np.ndarray  # (L, 2) int64: (height, width) of each level
    offsets: np.ndarray  # (L,) int64: start of each level in ``rest`` (0 for level 0)
    channels: int
    source: np.ndarray  # the source, H x W x C


def pyramid(src: np.ndarray, border: Border) -> Pyramid:
    """Box-filtered levels of ``src``: level 0 is ``src``, each next one halves it (2x2 mean).

    A finite source gives finite levels (a mean of values up to float32's largest is at most that).
    Halving stops at a level with an odd side (its seam or pole structure would shift by half a texel)
    or below 2 pixels. The extra levels take a third of the source's memory.
    """
    import cv2  # here: a warp that needs no pyramid starts without OpenCV

    levels = []
    cur = src
    while cur.shape[0] >= 2 and cur.shape[1] >= 2 and cur.shape[0] % 2 == 0 and cur.shape[1] % 2 == 0:
        nxt = cv2.resize(cur, (cur.shape[1] // 2, cur.shape[0] // 2), interpolation=cv2.INTER_AREA)
        if nxt.ndim == 2:
            nxt = nxt[..., None]
        nxt = np.ascontiguousarray(nxt, dtype=np.float32)
        if np.isinf(nxt).any() and not np.isinf(cur).any():  # OpenCV's float32 sums overflowed
            np.clip(nxt, -F32_MAX, F32_MAX, out=nxt)  # (an infinite source is left to the engine's repair)
        levels.append(nxt)
        cur = nxt
    shapes = np.array([src.shape[:2]] + [lv.shape[:2] for lv in levels], dtype=np.int64)
    sizes = [lv.size for lv in levels]
    offsets = np.concatenate([[0, 0], np.cumsum(sizes)[:-1]]).astype(np.int64)[:len(shapes)]
    rest = np.concatenate([lv.reshape(-1) for lv in levels]) if levels else np.zeros(1, np.float32)
    return Pyramid(src.reshape(-1), rest, shapes, offsets, src.shape[2], src)


def sample_footprint(pyr: Pyramid, band, border: Border, out: np.ndarray,
                     alpha: np.ndarray) -> None:
    """Fill ``out`` and ``alpha`` for a footprint band (see the module docstring)."""
    wrap, top, bottom = border.flags
    _footprint(pyr.level0, pyr.rest, pyr.shapes, pyr.offsets, band.xs, band.ys, band.valid & ~band.edge,
               band.foot, wrap, top, bottom, MAX_TAPS, DENSITY, AXIS_TOL, out, alpha)
    if len(band.edge_idx):
        _edges(pyr.source, band.edge_idx, band.edge_xs, band.edge_ys, band.edge_valid, band.xs.shape[2],
               wrap, top, bottom, out, alpha)


@numba.njit(inline="always", cache=True)
def _bilinear_at(img, x, y, wrap, top, bottom, acc, weight):
    sh, sw, nc = img.shape
    fx0 = np.floor(x)
    fy0 = np.floor(y)
    i0 = int(fx0)
    j0 = int(fy0)
    tx = x - fx0
    ty = y - fy0
    for dj in range(2):
        wy = ty if dj else 1.0 - ty
        if wy == 0.0:
            continue
        for di in range(2):
            wx = tx if di else 1.0 - tx
            if wx == 0.0:
                continue
            ii, jj = fold_index(i0 + di, j0 + dj, sw, sh, wrap, top, bottom)
            ww = weight * wx * wy
            for ch in range(nc):
                acc[ch] += ww * img[jj, ii, ch]


@numba.njit(inline="always", cache=True)
def _tent_cdf(u):
    """Integral of the tent max(0, 1 - |t|) from -inf to u: 0.5 + v - v|v|/2 with v = clip(u, -1, 1)
    (the two quadratic pieces in one branch-free form)."""
    v = min(1.0, max(-1.0, u))
    return 0.5 + v - 0.5 * v * abs(v)


@numba.njit(inline="always", cache=True)
def _tent_box_weights(x, width, i0, n, k):
    """``k[:n]`` = weights of texels ``i0..i0+n-1`` when the bilinear reconstruction is averaged over
    the box of ``width`` centred at ``x`` (the tent integrated over the box); returns their sum."""
    s = 0.0
    if width < 1e-6:
        for i in range(n):
            k[i] = max(0.0, 1.0 - abs(x - (i0 + i)))
            s += k[i]
        return s
    hw = 0.5 * width
    inv = 1.0 / width
    for i in range(n):
        d = x - (i0 + i)
        k[i] = (_tent_cdf(d + hw) - _tent_cdf(d - hw)) * inv
        s += k[i]
    return s


@kernel.options(fastmath=True)
def _footprint(level0, rest, shapes, offsets, xs, ys, valid, foot, wrap, top, bottom, max_taps, density,
               axis_tol, out, alpha):
    h, w, n = xs.shape
    nc = out.shape[2]
    nlev = shapes.shape[0]
    inv = 1.0 / n
    h0 = shapes[0, 0]
    for r in range(h):
        acc = np.zeros(nc)
        kx = np.zeros(WINDOW)
        ky = np.zeros(WINDOW)
        wgt = np.zeros((WINDOW, WINDOW))
        for c in range(w):
            acc[:] = 0.0
            a0 = 0.0
            a1 = 0.0
            a2 = 0.0
            hits = 0
            for k in range(n):
                if not valid[r, c, k]:
                    continue
                hits += 1
                ax = np.float64(foot[r, c, k, 0])
                ay = np.float64(foot[r, c, k, 1])
                bx = np.float64(foot[r, c, k, 2])
                by = np.float64(foot[r, c, k, 3])
                la = np.sqrt(ax * ax + ay * ay)
                lb = np.sqrt(bx * bx + by * by)
                longest = max(la, lb)
                lev = 0
                while lev + 1 < nlev and longest > max_taps * (1 << lev):
                    lev += 1
                lh = shapes[lev, 0]
                lw = shapes[lev, 1]
                scale = lh / h0  # texels of this level per source pixel
                # second moments of the footprint (a parallelogram), in texels^2 x 12: the variance
                # of a box of width w is w^2 / 12
                sxx = (ax * ax + bx * bx) * scale * scale
                syy = (ay * ay + by * by) * scale * scale
                sxy = (ax * ay + bx * by) * scale * scale
                cx = (np.float64(xs[r, c, k]) + 0.5) * scale - 0.5
                cy = (np.float64(ys[r, c, k]) + 0.5) * scale - 0.5
                if sxx <= 9.0 and syy <= 9.0 and abs(sxy) <= axis_tol:
                    na = nb = nsl = 1  # x-y covariance about 0: one box has the footprint's second moments
                    bw = np.sqrt(sxx)
                    bh = np.sqrt(syy)
                else:
                    # na x nb cells along the footprint's sides, each averaged over the axis-aligned
                    # box with its second moments
                    na = max(1, int(np.ceil(la * scale * density)))
                    nb = max(1, int(np.ceil(lb * scale * density)))
                    nsl = na * nb
                    bw = scale * np.sqrt((ax / na) ** 2 + (bx / nb) ** 2)
                    bh = scale * np.sqrt((ay / na) ** 2 + (by / nb) ** 2)
                bw = min(3.0, bw)
                bh = min(3.0, bh)
                buf = level0 if lev == 0 else rest
                base = offsets[lev]
                if nsl == 1:  # one box: separable weights, read directly
                    i0 = int(np.floor(cx - 1.0 - 0.5 * bw)) + 1
                    j0 = int(np.floor(cy - 1.0 - 0.5 * bh)) + 1
                    ni = int(np.floor(cx + 1.0 + 0.5 * bw)) + 1 - i0
                    nj = int(np.floor(cy + 1.0 + 0.5 * bh)) + 1 - j0
                    norm = 1.0 / (_tent_box_weights(cx, bw, i0, ni, kx) * _tent_box_weights(cy, bh, j0, nj, ky))
                    inside = i0 >= 0 and j0 >= 0 and i0 + ni <= lw and j0 + nj <= lh
                    for j in range(nj):
                        wj = ky[j] * norm
                        for i in range(ni):
                            ww = kx[i] * wj
                            if inside:
                                p = np.uint64(base + ((j0 + j) * lw + i0 + i) * nc)
                            else:
                                ii, jj = fold_index(i0 + i, j0 + j, lw, lh, wrap, top, bottom)
                                p = np.uint64(base + (jj * lw + ii) * nc)
                            if nc == 3:
                                a0 += ww * buf[p]
                                a1 += ww * buf[p + U1]
                                a2 += ww * buf[p + U2]
                            else:
                                for ch in range(nc):
                                    acc[ch] += ww * buf[p + np.uint64(ch)]
                    continue
                ex = 0.5 * scale * (abs(ax) * (1.0 - 1.0 / na) + abs(bx) * (1.0 - 1.0 / nb)) + 1.0 + 0.5 * bw
                ey = 0.5 * scale * (abs(ay) * (1.0 - 1.0 / na) + abs(by) * (1.0 - 1.0 / nb)) + 1.0 + 0.5 * bh
                wx0 = int(np.floor(cx - ex)) + 1
                wy0 = int(np.floor(cy - ey)) + 1
                nwx = min(int(np.floor(cx + ex)) - wx0 + 1, WINDOW)
                nwy = min(int(np.floor(cy + ey)) - wy0 + 1, WINDOW)
                for j in range(nwy):
                    for i in range(nwx):
                        wgt[j, i] = 0.0
                cell = 1.0 / nsl
                for q in range(nsl):
                    fa = (q % na + 0.5) / na - 0.5
                    fb = (q // na + 0.5) / nb - 0.5
                    px = cx + (fa * ax + fb * bx) * scale
                    py = cy + (fa * ay + fb * by) * scale
                    rx = 1.0 + 0.5 * bw
                    ry = 1.0 + 0.5 * bh
                    i0 = max(int(np.floor(px - rx)) + 1, wx0)
                    j0 = max(int(np.floor(py - ry)) + 1, wy0)
                    ni = min(int(np.floor(px + rx)) + 1, wx0 + nwx) - i0
                    nj = min(int(np.floor(py + ry)) + 1, wy0 + nwy) - j0
                    if ni <= 0 or nj <= 0:
                        continue
                    sx = _tent_box_weights(px, bw, i0, ni, kx)
                    sy = _tent_box_weights(py, bh, j0, nj, ky)
                    norm = cell / (sx * sy)
                    for j in range(nj):
                        wj = ky[j] * norm
                        for i in range(ni):
                            wgt[np.uint64(j0 - wy0 + j), np.uint64(i0 - wx0 + i)] += kx[i] * wj
                inside = wx0 >= 0 and wy0 >= 0 and wx0 + nwx <= lw and wy0 + nwy <= lh
                for j in range(nwy):
                    for i in range(nwx):
                        ww = wgt[j, i]
                        if ww == 0.0:
                            continue
                        if inside:
                            p = np.uint64(base + ((wy0 + j) * lw + wx0 + i) * nc)
                        else:
                            ii, jj = fold_index(wx0 + i, wy0 + j, lw, lh, wrap, top, bottom)
                            p = np.uint64(base + (jj * lw + ii) * nc)
                        if nc == 3:
                            a0 += ww * buf[p]
                            a1 += ww * buf[p + U1]
                            a2 += ww * buf[p + U2]
                        else:
                            for ch in range(nc):
                                acc[ch] += ww * buf[p + np.uint64(ch)]
            if nc == 3:
                acc[0] = a0
                acc[1] = a1
                acc[2] = a2
            for ch in range(nc):
                out[r, c, ch] = acc[ch] * inv
            alpha[r, c] = hits * inv


@numba.njit(cache=True, nogil=True)
def _edges(src, idx, exs, eys, evalid, n, wrap, top, bottom, out, alpha):
    """Add the split edge samples: each contributes (sum of its valid sub-samples) / (K n)."""
    nc = out.shape[2]
    w = out.shape[1]
    m, kk = exs.shape
    acc = np.zeros(nc)
    for e in range(m):
        pix = idx[e] // n
        r = pix // w
        c = pix % w
        acc[:] = 0.0
        hits = 0
        for q in range(kk):
            if evalid[e, q]:
                hits += 1
                _bilinear_at(src, np.float64(exs[e, q]), np.float64(eys[e, q]), wrap, top, bottom, acc, 1.0)
        scale = 1.0 / (kk * n)
        for ch in range(nc):
            out[r, c, ch] += acc[ch] * scale
        alpha[r, c] += hits * scale
