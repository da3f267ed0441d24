"""The sweep: repair, expose and map an image block by block, in cache-sized pieces.

Each block is checked for bad values in one pass over its bit patterns; only a block that holds NaN,
infinities or negatives is repaired (NaN and negatives -> 0, +inf -> white after the curve) and
counted. Then the curve's kernel (see :mod:`lenslab.tone.kernels`) runs on the block: on every value,
on planar RGB triples, or on luminance with RGB scaled by ``curve(L) / L``.
"""

from __future__ import annotations

import os

import numpy as np

from lenslab.tone.kernels import F32, TINY, clip

BLOCK = 1 << 16  # values per block: the block and two scratch buffers stay inside a core's L2 cache
THREAD_MIN = 1 << 19  # values a thread must have to be worth starting (8 blocks)


def available_cores() -> int:
    """Cores this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - platforms without affinity
        return os.cpu_count() or 1


def run_split(sweep, src: np.ndarray, dst: np.ndarray, kernel, extra: tuple, counts: "Counts",
              threads: int | None = None) -> None:
    """``sweep(src, dst, kernel, *extra, counts)`` over contiguous pieces of the rows of ``src`` on up
    to ``threads`` threads (None: every core; NumPy's ufuncs release the GIL), counts added up. The
    pieces are whole blocks, so the result is the same for any number of threads."""
    rows = src.shape[0]
    per_row = src.size // max(rows, 1)
    n = available_cores() if threads is None else max(1, int(threads))
    n = max(1, min(n, src.size // THREAD_MIN))
    if n == 1:
        sweep(src, dst, kernel, *extra, counts)
        return
    from concurrent.futures import ThreadPoolExecutor

    step = BLOCK // per_row
    piece = -(-rows // n)
    piece = -(-piece // step) * step
    parts = [(s, min(s + piece, rows)) for s in range(0, rows, piece)]
    tallies = [Counts() for _ in parts]
    state = np.geterr()  # NumPy's error state is per thread: the workers take the caller's

    def work(job):
        (a, b), tally = job
        with np.errstate(**state):
            sweep(src[a:b], dst[a:b], kernel, *extra, tally)

    with ThreadPoolExecutor(len(parts)) as pool:
        list(pool.map(work, zip(parts, tallies)))
    for t in tallies:
        counts.add(t)


class Counts:
    __slots__ = ("nan", "posinf", "negative", "lowest")

    def __init__(self):
        self.nan = self.posinf = self.negative = 0
        self.lowest = 0.0  # the most negative value repaired (-inf included)

    def any(self) -> bool:
        return bool(self.nan or self.posinf or self.negative)

    def add(self, other: "Counts") -> None:
        self.nan += other.nan
        self.posinf += other.posinf
        self.negative += other.negative
        self.lowest = min(self.lowest, other.lowest)


def repair(block: np.ndarray, counts: Counts) -> np.ndarray:
    """Repair a block in place (NaN, negatives -> 0; +inf -> 0 for now); return the +inf mask."""
    nan = np.isnan(block)
    posinf = np.isposinf(block)
    neg = block < 0
    counts.nan += int(np.count_nonzero(nan))
    counts.posinf += int(np.count_nonzero(posinf))
    n_neg = int(np.count_nonzero(neg))
    counts.negative += n_neg
    if n_neg:
        counts.lowest = min(counts.lowest, float(block[neg].min()))
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
    NumPy kernels see planar (3, m) blocks: contiguous rows keep every ufunc on the fast path; compiled
    pixel kernels (:func:`lenslab.tone.kernels.pixel_kernel`) read the pixels as they are."""
    if getattr(kernel, "pixels", False):
        _sweep_pixels(px, out, kernel, counts)
        return
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


def _sweep_pixels(px: np.ndarray, out: np.ndarray, kernel, counts: Counts) -> None:
    """A pixel kernel over contiguous (n, 3) float32 pixels: one pass per block; a block that held bad
    values is mapped again from a repaired copy."""
    if np.may_share_memory(px, out):
        px = px.copy()  # the second pass of a block with bad values reads its input again
    step = BLOCK // 3
    for s in range(0, px.shape[0], step):
        src, dst = px[s:s + step], out[s:s + step]
        if kernel(src, dst) >= FIRST_NOT_CLEAN:
            fixed = src.copy()
            inf_px = repair(fixed, counts).any(axis=1)
            kernel(fixed, dst)
            dst[inf_px] = 1


COMPILED_PASSES: bool | None = None  # None: as compiled_ready() says; True or False forces (benchmarks, tests)


def compiled_ready() -> bool:
    """Whether the luminance mode takes its compiled passes: once numba is loaded in this process (a
    warp, a batch of files, a Python session that warped). Loading numba and its cached kernels takes
    about 0.5 s, more than the NumPy passes spend on any one image of a few hundred megapixels, so a
    command that tone-maps one image does not pay it. Both give the same bits. ``COMPILED_PASSES``
    overrides the choice."""
    import sys

    return "numba" in sys.modules if COMPILED_PASSES is None else bool(COMPILED_PASSES)


def sweep_luminance(px: np.ndarray, out: np.ndarray, kernel, weights, counts: Counts) -> None:
    """Curve on luminance, RGB scaled by curve(L)/L; over-range pixels blended toward grey.

    The steps, in float32 and in this order (:mod:`lenslab.tone.luminance` gives them in full):
    ``L = (w0 r + w1 g) + w2 b``; ``Ld = curve(L)``; ``c *= Ld / (L + TINY)`` for each channel;
    ``t = clip((1 - Ld) / max(peak - Ld, TINY), 0, 1)`` with ``peak`` the largest scaled channel;
    ``c = clip(Ld + (c - Ld) t, 0, 1)``; a pixel with a +inf channel is white. Two executions of them
    give the same bits: compiled passes over the interleaved pixels (:func:`compiled_ready`), or
    NumPy's ufuncs over a planar copy of each block."""
    if compiled_ready():
        _luminance_compiled(px, out, kernel, weights, counts)
    else:
        _luminance_numpy(px, out, kernel, weights, counts)


def _luminance_numpy(px, out, kernel, weights, counts: Counts) -> None:
    n = px.shape[0]
    step = BLOCK // 3
    size = min(step, n)
    w = [F32(v) for v in np.asarray(weights, dtype=F32).reshape(3)]
    pl = np.empty((3, size), F32)
    lum, mapped, peak, tmp = (np.empty(size, F32) for _ in range(4))
    scratch = [np.empty(size, F32) for _ in range(2)]
    for s in range(0, n, step):
        e = min(s + step, n)
        m = e - s
        src, dst = px[s:e], out[s:e]
        p = pl[:, :m]
        p[...] = src.T
        L, Ld, pk, u = lum[:m], mapped[:m], peak[:m], tmp[:m]
        inf_cols = None
        if not is_clean(p):
            inf_cols = repair(p, counts).any(axis=0)
        np.multiply(p[0], w[0], out=L)
        np.multiply(p[1], w[1], out=u)
        L += u
        np.multiply(p[2], w[2], out=u)
        L += u
        kernel(L, Ld, [t[:m] for t in scratch])
        np.add(L, TINY, out=u)
        np.divide(Ld, u, out=u)                  # k = Ld / (L + TINY)
        p *= u
        np.fmax(p[0], p[1], out=pk)
        np.fmax(pk, p[2], out=pk)
        pk -= Ld
        np.fmax(pk, TINY, out=pk)
        np.subtract(F32(1), Ld, out=u)
        u /= pk
        clip(u, F32(0), F32(1), out=u)           # t
        p -= Ld
        p *= u
        p += Ld
        if inf_cols is not None:
            p[:, inf_cols] = 1
        for c in range(3):                       # the clip to [0, 1] is the copy back
            clip(p[c], F32(0), F32(1), out=dst[:, c])


def _luminance_compiled(px, out, kernel, weights, counts: Counts) -> None:
    from lenslab.tone.luminance import scale_clean, scale_pixels, weigh_clean, weigh_pixels

    n = px.shape[0]
    step = BLOCK // 3
    size = min(step, n)
    w0, w1, w2 = (F32(v) for v in np.asarray(weights, dtype=F32).reshape(3))
    lum, mapped = np.empty(size, F32), np.empty(size, F32)
    scratch = [np.empty(size, F32) for _ in range(2)]
    for s in range(0, n, step):
        e = min(s + step, n)
        m = e - s
        L, Ld = lum[:m], mapped[:m]
        block = px[s:e]
        flat = block.reshape(-1)
        clean = weigh_clean(flat, flat.view(np.uint32), w0, w1, w2, L) < FIRST_NOT_CLEAN
        if not clean:
            nan, posinf, neg, lowest = weigh_pixels(block, w0, w1, w2, L)
            counts.nan += nan
            counts.posinf += posinf
            counts.negative += neg
            counts.lowest = min(counts.lowest, float(lowest))
        kernel(L, Ld, [t[:m] for t in scratch])
        if clean:
            scale_clean(flat, L, Ld, out[s:e].reshape(-1))
        else:
            scale_pixels(block, L, Ld, out[s:e])
