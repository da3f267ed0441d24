"""The sweep: repair, expose and map an image block by block, in cache-sized pieces.

Each block is checked for bad values in one pass over its bit patterns; only a block that holds NaN,
infinities or negatives is repaired (NaN and negatives -> 0, +inf -> white after the curve) and
counted. Then the curve's kernel (see :mod:`lenslab.tone.kernels`) runs on the block: on every value,
on planar RGB triples, or on luminance with RGB scaled by ``curve(L) / L``.
"""

from __future__ import annotations

import numpy as np

from lenslab.tone.kernels import F32, FMAX, TINY, clip

BLOCK = 1 << 16  # values per block: the block and two scratch buffers stay inside a core's L2 cache


class Counts:
    __slots__ = ("nan", "posinf", "negative")

    def __init__(self):
        self.nan = self.posinf = self.negative = 0

    def any(self) -> bool:
        return bool(self.nan or self.posinf or self.negative)


def repair(block: np.ndarray, counts: Counts) -> np.ndarray:
    """Repair a block in place (NaN, negatives -> 0; +inf -> 0 for now); return the +inf mask."""
    nan = np.isnan(block)
    posinf = np.isposinf(block)
    neg = block < 0
    counts.nan += int(np.count_nonzero(nan))
    counts.posinf += int(np.count_nonzero(posinf))
    counts.negative += int(np.count_nonzero(neg))
    block[nan | posinf | neg] = 0
    return posinf


FIRST_NOT_CLEAN = np.uint32(0x7F800000)  # +inf's bits; NaN lie above, negatives (sign bit set) far above


def is_clean(block: np.ndarray) -> bool:
    """True when every float32 value is finite and >= +0, tested in one sweep on the bit patterns."""
    return bool(block.view(np.uint32).max() < FIRST_NOT_CLEAN)


def sweep_values(flat: np.ndarray, out: np.ndarray, kernel, counts: Counts) -> None:
    """Per-value curve over 1-D float32 ``flat`` into ``out`` (may be the same array)."""
    n = flat.size
    scratch = [np.empty(min(BLOCK, n), F32) for _ in range(2)]
    for s in range(0, n, BLOCK):
        e = min(s + BLOCK, n)
        src, dst = flat[s:e], out[s:e]
        inf_mask = None
        if not is_clean(src):
            if dst is not src:
                np.copyto(dst, src)
            inf_mask = repair(dst, counts)
            src = dst
        kernel(src, dst, [t[: e - s] for t in scratch])
        if inf_mask is not None:
            dst[inf_mask] = 1


def sweep_rgb(px: np.ndarray, out: np.ndarray, kernel, counts: Counts) -> None:
    """RGB curve over (n, 3) float32 pixels into ``out``; a pixel with a +inf channel becomes white.
    Kernels see planar (3, m) blocks: contiguous rows keep every ufunc on the fast path."""
    n = px.shape[0]
    step = BLOCK // 3
    planes = [np.empty((3, min(step, n)), F32) for _ in range(4)]
    for s in range(0, n, step):
        e = min(s + step, n)
        m = e - s
        src, dst = px[s:e], out[s:e]
        pin, pout, t1, t2 = (p[:, :m] for p in planes)
        np.copyto(pin, src.T)
        inf_cols = None
        if not is_clean(pin):
            inf_cols = repair(pin, counts).any(axis=0)
        kernel(pin, pout, [t1, t2])
        if inf_cols is not None:
            pout[:, inf_cols] = 1
        for c in range(3):
            dst[:, c] = pout[c]


def sweep_luminance(px: np.ndarray, out: np.ndarray, kernel, weights, counts: Counts) -> None:
    """Curve on luminance, RGB scaled by curve(L)/L; over-range pixels blended toward grey.

    One planar copy of each block (contiguous rows keep every ufunc on its fast path); the scaling
    and the blend toward grey are one multiply-add per channel with per-pixel factors."""
    n = px.shape[0]
    step = BLOCK // 3
    size = min(step, n)
    w = np.asarray(weights, dtype=F32).reshape(1, 3)
    pl = np.empty((3, size), F32)
    lum, mapped, ratio, peak = (np.empty(size, F32) for _ in range(4))
    scratch = [np.empty(size, F32) for _ in range(2)]
    big = FMAX
    for s in range(0, n, step):
        e = min(s + step, n)
        m = e - s
        src, dst = px[s:e], out[s:e]
        p = pl[:, :m]
        np.copyto(p, src.T)
        L, Ld, r, pk = lum[:m], mapped[:m], ratio[:m], peak[:m]
        inf_cols = None
        if not is_clean(p):
            inf_cols = repair(p, counts).any(axis=0)
        np.fmax(p[0], p[1], out=pk)
        np.fmax(pk, p[2], out=pk)               # the brightest channel
        np.matmul(w, p, out=L[None])
        kernel(L, Ld, [t[:m] for t in scratch])
        L += TINY                              # exact above 1e-30; curve(0) = 0: black gets ratio 0
        np.divide(Ld, L, out=r)
        pk *= r                                 # the brightest channel after scaling
        if pk.max() > 1:
            # blend toward grey (Ld, Ld, Ld) until the peak fits: out = Ld + (p r - Ld) t with
            # t = (1 - Ld) / (peak - Ld) clipped to [0, 1], i.e. p (r t) + Ld (1 - t) in one sweep
            # (t = 1, offset exactly 0, wherever the peak is within range)
            t, b = scratch[0][:m], scratch[1][:m]
            pk -= Ld
            clip(pk, TINY, big, out=pk)
            np.subtract(F32(1), Ld, out=t)
            t /= pk
            clip(t, F32(0), F32(1), out=t)
            r *= t
            np.multiply(Ld, t, out=b)
            np.subtract(Ld, b, out=b)
            p *= r
            p += b
            clip(p, F32(0), F32(1), out=p)
        else:
            p *= r
        if inf_cols is not None:
            p[:, inf_cols] = 1
        for c in range(3):
            dst[:, c] = p[c]

