"""Reconstruction filters: read a float32 source at fractional positions, exactly.

Each sampler takes a band of the map (source index coordinates per output sample, the centre of
source pixel ``(i, j)`` at ``(i, j)``) and returns, per output pixel, the *sum of its valid samples
divided by the number of samples* (colour premultiplied by coverage) and the coverage itself.

Filters (separable, weights computed in float64 from the exact fractional position):

- ``nearest``: the pixel whose centre is nearest (ties go right/down);
- ``bilinear``: the 2x2 tent, ``w(t) = 1 - |t|``;
- ``bicubic``: Catmull-Rom (Keys' cubic with ``a = -0.5``), 4x4 taps; interpolating, reproduces
  quadratics, overshoots a little at sharp edges (never clamped: HDR stays HDR);
- ``lanczos``: Lanczos-3 windowed sinc, 6x6 taps, weights normalised to sum to 1.

A finite source gives a finite output: where the overshoot of bicubic or lanczos next to a value
near float32's largest would pass it, the output holds the largest float32 (as +-inf in a source
is read, see :func:`finite_source`).

Why not ``cv2.remap``: with float maps cv2 rounds the fractional position to 1/32 pixel
(``INTER_BITS = 5``), an error of up to 1/64 pixel times the local gradient; in HDR images with
sharp bright sources that reaches percent-level errors per pixel (measured by ``lenslab bench warp``),
and it cannot fold taps across the poles. These samplers use the exact position, fold every tap
through :mod:`lenslab.warp.seam` and run compiled (numba), one band of rows per thread. Bilinear weights are float32
(exact at pixel centres; 2^-24 relative elsewhere), the others float64.
"""

from __future__ import annotations

import numba
import numpy as np

from lenslab.warp.dispatch import kernel
from lenslab.warp.seam import fold_index, fold_piece, piece_at

FILTERS = ("nearest", "bilinear", "bicubic", "lanczos")
#: the largest float32: where a filter's overshoot would pass it, the output holds it instead of inf
F32_MAX = float(np.finfo(np.float32).max)
U1, U2 = np.uint64(1), np.uint64(2)  # channel offsets added to unsigned flat indices
#: filter name -> compiled kernel id (also its support radius in source pixels, but 1 for nearest)
_KIND = {"nearest": 0, "bilinear": 1, "bicubic": 2, "lanczos": 3}


def sample(src: np.ndarray, xs: np.ndarray, ys: np.ndarray, valid: np.ndarray, border, filter: str,
           out: np.ndarray, alpha: np.ndarray) -> None:
    """Fill ``out`` (h, W, C) float32 and ``alpha`` (h, W) float32 from a map band (h, W, S).

    A source whose pieces have neighbours (``border.has_pieces``, a cube map) is read through the
    separable sampler, whose taps leaving a sample's piece read the neighbouring piece."""
    kind = _KIND[filter]
    wrap, top, bottom = border.flags
    if kind == 1 and not border.has_pieces:
        sh, sw, nc = src.shape
        if xs.shape[2] == 1:  # one sample per pixel: 2-D maps (views, no copy)
            one = _bilinear1_rgb if nc == 3 else _bilinear1
            one(src.reshape(-1), sw, sh, nc, xs[..., 0], ys[..., 0], valid[..., 0], wrap, top, bottom, out, alpha)
        else:
            _bilinear(src.reshape(-1), sw, sh, nc, xs, ys, valid, wrap, top, bottom, out, alpha)
    else:
        cw, ch = border.cell
        _separable(src, xs, ys, valid, wrap, top, bottom, border.pieces, border.grid, cw, ch, kind, out, alpha)


@numba.njit(inline="always", cache=True)
def _corner_offsets(i0, j0, sw, sh, nc, wrap, top, bottom):
    """Flat offsets of the 2x2 taps at (i0..i0+1, j0..j0+1), folded by the border rules if needed.

    Unsigned (uint64): an index of a signed type costs a test for a negative index at every read (numba
    wraps those around, as Python does), which took as long as the reads themselves; add channel numbers
    as uint64 too (``p + U[ch]``: uint64 plus int64 would be a float)."""
    if i0 >= 0 and j0 >= 0 and i0 + 1 < sw and j0 + 1 < sh:
        p00 = (j0 * sw + i0) * nc
        return (np.uint64(p00), np.uint64(p00 + nc), np.uint64(p00 + sw * nc), np.uint64(p00 + sw * nc + nc))
    ia, ja = fold_index(i0, j0, sw, sh, wrap, top, bottom)
    ib, jb = fold_index(i0 + 1, j0, sw, sh, wrap, top, bottom)
    ic, jc = fold_index(i0, j0 + 1, sw, sh, wrap, top, bottom)
    id_, jd = fold_index(i0 + 1, j0 + 1, sw, sh, wrap, top, bottom)
    return (np.uint64((ja * sw + ia) * nc), np.uint64((jb * sw + ib) * nc), np.uint64((jc * sw + ic) * nc),
            np.uint64((jd * sw + id_) * nc))


# fastmath: these loops only multiply and add finite weights; a non-finite source value that reaches
# the output is caught afterwards and the warp redone from a repaired source (see engine.WarpPlan.run)
@kernel.options(fastmath=True, error_model="numpy")
def _bilinear(flat, sw, sh, nc, xs, ys, valid, wrap, top, bottom, out, alpha):
    h, w, n = xs.shape
    inv = np.float32(1.0 / n)
    for r in range(h):
        acc = np.zeros(nc, dtype=np.float32)
        for c in range(w):
            a0 = np.float32(0.0)
            a1 = np.float32(0.0)
            a2 = np.float32(0.0)
            acc[:] = 0.0
            hits = 0
            for k in range(n):
                if not valid[r, c, k]:
                    continue
                hits += 1
                x = xs[r, c, k]
                y = ys[r, c, k]
                fx0 = np.floor(x)
                fy0 = np.floor(y)
                tx = x - fx0
                ty = y - fy0
                p00, p10, p01, p11 = _corner_offsets(int(fx0), int(fy0), sw, sh, nc, wrap, top, bottom)
                w00 = (1 - tx) * (1 - ty)
                w10 = tx * (1 - ty)
                w01 = (1 - tx) * ty
                w11 = tx * ty
                if nc == 3:
                    a0 += w00 * flat[p00] + w10 * flat[p10] + w01 * flat[p01] + w11 * flat[p11]
                    a1 += (w00 * flat[p00 + U1] + w10 * flat[p10 + U1] + w01 * flat[p01 + U1]
                           + w11 * flat[p11 + U1])
                    a2 += (w00 * flat[p00 + U2] + w10 * flat[p10 + U2] + w01 * flat[p01 + U2]
                           + w11 * flat[p11 + U2])
                else:
                    for ch in range(nc):
                        kc = np.uint64(ch)
                        acc[ch] += (w00 * flat[p00 + kc] + w10 * flat[p10 + kc] + w01 * flat[p01 + kc]
                                    + w11 * flat[p11 + kc])
            if nc == 3:
                out[r, c, 0] = a0 * inv
                out[r, c, 1] = a1 * inv
                out[r, c, 2] = a2 * inv
            else:
                for ch in range(nc):
                    out[r, c, ch] = acc[ch] * inv
            alpha[r, c] = hits * inv


@numba.njit(inline="always", cache=True)
def lerp_at(flat, sw, sh, nc, x, y, wrap, top, bottom, out, r, c):
    """``out[r, c]`` = the source bilinearly at float32 index coordinates ``(x, y)`` (lerps in float32)."""
    fx0 = np.floor(x)
    fy0 = np.floor(y)
    tx = x - fx0
    ty = y - fy0
    p00, p10, p01, p11 = _corner_offsets(np.int32(fx0), np.int32(fy0), sw, sh, nc, wrap, top, bottom)
    lerp_n(flat, p00, p10, p01, p11, tx, ty, nc, out[r], c)


@numba.njit(inline="always", cache=True)
def lerp_n(flat, p00, p10, p01, p11, tx, ty, nc, orow, c):
    """``orow[c, 0:nc]`` = the ``nc`` channels bilinearly from the taps at unsigned flat offsets ``p00, p10,
    p01, p11`` (top-left, top-right, bottom-left, bottom-right), in float32 lerps (:func:`lerp3` for three)."""
    for ch in range(nc):
        kc = np.uint64(ch)
        a = flat[p00 + kc]
        b = flat[p01 + kc]
        upper = a + tx * (flat[p10 + kc] - a)
        lower = b + tx * (flat[p11 + kc] - b)
        orow[c, ch] = upper + ty * (lower - upper)


@kernel.options(fastmath=True, error_model="numpy")
def _bilinear1(flat, sw, sh, nc, xs, ys, valid, wrap, top, bottom, out, alpha):
    """One sample per pixel (the common case, and the cached-map batch path): no accumulation, lerps."""
    h, w = xs.shape
    for r in range(h):
        for c in range(w):
            if not valid[r, c]:
                for ch in range(nc):
                    out[r, c, ch] = 0.0
                alpha[r, c] = 0.0
                continue
            lerp_at(flat, sw, sh, nc, xs[r, c], ys[r, c], wrap, top, bottom, out, r, c)
            alpha[r, c] = 1.0


@numba.njit(inline="always", cache=True)
def lerp3(flat, p00, p10, p01, p11, tx, ty, orow, c):
    """``orow[c, 0:3]`` = the three channels bilinearly from the taps at unsigned flat offsets
    ``p00, p10, p01, p11`` (top-left, top-right, bottom-left, bottom-right), in float32 lerps."""
    a = flat[p00]
    b = flat[p01]
    upper = a + tx * (flat[p10] - a)
    lower = b + tx * (flat[p11] - b)
    orow[c, 0] = upper + ty * (lower - upper)
    a = flat[p00 + U1]
    b = flat[p01 + U1]
    upper = a + tx * (flat[p10 + U1] - a)
    lower = b + tx * (flat[p11 + U1] - b)
    orow[c, 1] = upper + ty * (lower - upper)
    a = flat[p00 + U2]
    b = flat[p01 + U2]
    upper = a + tx * (flat[p10 + U2] - a)
    lower = b + tx * (flat[p11 + U2] - b)
    orow[c, 2] = upper + ty * (lower - upper)


@kernel.options(fastmath=True, error_model="numpy")
def _bilinear1_rgb(flat, sw, sh, nc, xs, ys, valid, wrap, top, bottom, out, alpha):
    """:func:`_bilinear1` for three channels, row by row through 1-D views, the channels written out."""
    h, w = xs.shape
    for r in range(h):
        xr = xs[r]
        yr = ys[r]
        vr = valid[r]
        orow = out[r]
        arow = alpha[r]
        for c in range(w):
            if not vr[c]:
                orow[c, 0] = 0.0
                orow[c, 1] = 0.0
                orow[c, 2] = 0.0
                arow[c] = 0.0
                continue
            x = xr[c]
            y = yr[c]
            fx0 = np.floor(x)
            fy0 = np.floor(y)
            tx = x - fx0
            ty = y - fy0
            p00, p10, p01, p11 = _corner_offsets(np.int32(fx0), np.int32(fy0), sw, sh, 3, wrap, top, bottom)
            lerp3(flat, p00, p10, p01, p11, tx, ty, orow, c)
            arow[c] = 1.0


@numba.njit(inline="always", cache=True)
def _weight(kind, t):
    a = abs(t)
    if kind == 1:  # tent
        return max(0.0, 1.0 - a)
    if kind == 2:  # Catmull-Rom
        if a < 1.0:
            return (1.5 * a - 2.5) * a * a + 1.0
        if a < 2.0:
            return ((-0.5 * a + 2.5) * a - 4.0) * a + 2.0
        return 0.0
    # Lanczos-3
    if a == 0.0:
        return 1.0
    if a >= 3.0:
        return 0.0
    pa = np.pi * a
    return 3.0 * np.sin(pa) * np.sin(pa / 3.0) / (pa * pa)


@numba.njit(inline="always", cache=True)
def _fold(i, j, sw, sh, wrap, top, bottom, piece, table):
    if piece >= 0:
        return fold_piece(i, j, piece, table)
    return fold_index(i, j, sw, sh, wrap, top, bottom)


@kernel
def _separable(src, xs, ys, valid, wrap, top, bottom, table, grid, cw, ch, kind, out, alpha):
    h, w, n = xs.shape
    sh, sw, nc = src.shape
    inv = 1.0 / n
    rad = max(kind, 1)
    pieces = table.shape[0] > 0
    for r in range(h):
        acc = np.zeros(nc)
        wx = np.zeros(2 * rad)
        wy = np.zeros(2 * rad)
        for c in range(w):
            acc[:] = 0.0
            hits = 0
            for k in range(n):
                if not valid[r, c, k]:
                    continue
                hits += 1
                x = np.float64(xs[r, c, k])
                y = np.float64(ys[r, c, k])
                piece = piece_at(x, y, grid, cw, ch) if pieces else -1
                if kind == 0:
                    ii, jj = _fold(int(np.floor(x + 0.5)), int(np.floor(y + 0.5)), sw, sh, wrap, top, bottom,
                                   piece, table)
                    for ch_ in range(nc):
                        acc[ch_] += src[jj, ii, ch_]
                    continue
                i0 = int(np.floor(x))
                j0 = int(np.floor(y))
                sx = 0.0
                sy = 0.0
                for t in range(2 * rad):
                    wx[t] = _weight(kind, x - (i0 - rad + 1 + t))
                    wy[t] = _weight(kind, y - (j0 - rad + 1 + t))
                    sx += wx[t]
                    sy += wy[t]
                for tj in range(2 * rad):
                    if wy[tj] == 0.0:
                        continue
                    for ti in range(2 * rad):
                        ww = wx[ti] * wy[tj]
                        if ww == 0.0:
                            continue
                        ww /= sx * sy
                        ii, jj = _fold(i0 - rad + 1 + ti, j0 - rad + 1 + tj, sw, sh, wrap, top, bottom, piece, table)
                        ui, uj = np.uint64(ii), np.uint64(jj)  # folded: never negative (no wraparound test)
                        for ch_ in range(nc):
                            acc[ch_] += ww * src[uj, ui, ch_]
            for ch_ in range(nc):
                v = acc[ch_] * inv
                # negative lobes overshoot: a finite source stays finite (its extremes are float32's)
                if v > F32_MAX:
                    v = F32_MAX
                elif v < -F32_MAX:
                    v = -F32_MAX
                out[r, c, ch_] = v
            alpha[r, c] = hits * inv


def all_finite(a: np.ndarray) -> bool:
    """True when every value of ``a`` is finite (no temporary arrays; a large array in pieces on the
    engine's threads)."""
    from lenslab.warp.dispatch import run_bands

    flat = np.ascontiguousarray(a).reshape(-1)
    step = max(1 << 22, -(-flat.size // 8))
    if flat.size <= step:
        return bool(_all_finite(flat))
    return all(run_bands([flat[i:i + step] for i in range(0, flat.size, step)], _all_finite))


@numba.njit(cache=True, nogil=True)
def _all_finite(flat):
    for i in range(flat.size):
        if not np.isfinite(flat[i]):
            return False
    return True


def finite_source(src: np.ndarray) -> tuple[np.ndarray, int]:
    """``src`` itself when all finite, else a copy with NaN -> 0 and +-inf -> +-float32 max; and the count."""
    if all_finite(src):
        return src, 0
    bad = int(np.count_nonzero(~np.isfinite(src)))
    big = np.finfo(np.float32).max
    return np.nan_to_num(src, nan=0.0, posinf=big, neginf=-big), bad
