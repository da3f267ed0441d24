"""The footprint prefilter's source side: a box-filtered pyramid of the source and the compiled
sampler that averages it over each output sample's footprint (see :mod:`lenslab.warp.antialias` for
the method and the footprints themselves). The sampler is C++ compiled ahead of time
(:mod:`lenslab.warp.kernels.native`, ``src/native/footprint_runs.cpp``);
:func:`lenslab.warp.kernels.reference.footprint` is its NumPy reference. A warp builds its pyramid lazily: only
the rows of the coarser levels that its footprints read (:meth:`Pyramid.ensure`)."""

from __future__ import annotations

import math
import threading
from dataclasses import dataclass, field

import numpy as np

from lenslab.warp.kernels import native
from lenslab.warp.kernels.dispatch import run_bands, threads
from lenslab.warp.kernels.native import c32, cbool
from lenslab.warp.seam import Border

MAX_TAPS = 8.0  # longest side of a footprint, in texels of the level it is read from (a coarser level
#               blurs: at 4 the error on forest.exr doubles; measured in docs/design.md)
WINDOW = 24  # texels: the side of the window of weights a footprint is gathered through (fits 2 MAX_TAPS + 3;
#              the same constant in src/native/footprint_edges.h)
THIN = 1e-3  # texels: a footprint thinner than this (a line, a point) is given this thickness


@dataclass
class Pyramid:
    """Box-filtered levels of a source: level 0 is the source itself, the others packed in one buffer.

    A lazy pyramid builds the rows of levels 1.. as footprints first need them (:meth:`ensure`): the rest of its
    buffer is never written, so never given memory (a fisheye of a panorama reads the coarser levels near the
    poles only)."""

    level0: np.ndarray  # the source, flattened (a view, no copy)
    rest: np.ndarray  # levels 1.. one after the other, flattened float32
    shapes: np.ndarray  # (L, 2) int64: (height, width) of each level
    offsets: np.ndarray  # (L,) int64: start of each level in ``rest`` (0 for level 0)
    channels: int
    source: np.ndarray  # the source, H x W x C
    built: list = field(default_factory=list)  # per level >= 1: bool (rows,), the rows already built
    lock: threading.Lock = field(default_factory=threading.Lock)

    def level(self, lev: int) -> np.ndarray:
        """Level ``lev`` as an (h, w, C) array (a view)."""
        if lev == 0:
            return self.source
        h, w = self.shapes[lev]
        off = self.offsets[lev]
        return self.rest[off:off + h * w * self.channels].reshape(h, w, self.channels)

    def build(self, lev: int, r0: int, r1: int) -> None:
        """Rows ``r0:r1`` of level ``lev`` >= 1 (those of the finer levels they come from first)."""
        done = self.built[lev - 1]
        seg = done[r0:r1]
        if seg.all():
            return
        # the runs of missing rows: built rows are never written again (other bands may be reading them without
        # the GIL); mostly none of the rows is built yet, one run
        runs = [(r0, r1)]
        if seg.any():
            todo = np.flatnonzero(~seg) + r0
            breaks = np.flatnonzero(np.diff(todo) > 1) + 1
            runs = [(int(run[0]), int(run[-1]) + 1) for run in np.split(todo, breaks)]
        cur, nxt = self.level(lev - 1), self.level(lev)
        k = native.kernels()
        for a, b in runs:
            if lev > 1:
                self.build(lev - 1, 2 * a, 2 * b)
            k.halve(c32(cur[2 * a:2 * b]), nxt[a:b])
            done[a:b] = True

    def ensure(self, ys, valid, foot, coarse=None) -> None:
        """Build the rows of the coarser levels that the valid footprints at rows ``ys`` (source pixels, index
        coordinates) with sides ``foot`` (..., 4) read: the level and the window the filter picks, a texel wider
        (compiled: ``level_rows``, reference :func:`lenslab.warp.kernels.reference.level_rows`), rows beyond a
        pole or an edge folded back. ``coarse``: int64 flat indices of the samples that may leave level 0 (every
        other footprint spans at most ``MAX_TAPS`` texels; :attr:`FootprintBand.coarse`); None: look at all."""
        if all(d.all() for d in self.built):
            return
        rows = np.empty((len(self.shapes), 2), np.int64)
        idx = None if coarse is None else np.ascontiguousarray(coarse, dtype=np.int64)
        native.kernels().level_rows(self.shapes, c32(ys), cbool(valid), c32(foot), MAX_TAPS, rows, idx)
        with self.lock:
            for k in range(1, len(self.shapes)):
                lo, hi = (int(v) for v in rows[k])
                if lo == np.iinfo(np.int64).max:  # no footprint reads this level
                    continue
                lh = int(self.shapes[k][0])
                if lo >= hi:  # every window beyond an edge (clamped to +-lh): the rows the filter folds to
                    lo, hi = 0, lh
                if lo < 0:  # rows above the top come back from below it (a pole) or are row 0
                    hi = max(hi, -lo)
                if hi > lh:  # and those below the bottom from above it
                    lo = min(lo, 2 * lh - hi)
                self.build(k, max(0, lo), min(lh, max(hi, 1)))


def pyramid(src: np.ndarray, border: Border, lazy: bool = False) -> Pyramid:
    """Box-filtered levels of ``src`` (float32 H x W x C): level 0 is ``src``, each next one halves it (2x2
    mean, summed in float64: a finite source gives finite levels; compiled, one band of rows per thread).

    Halving stops at a level with an odd side (its seam or pole structure would shift by half a texel)
    or below 2 pixels. The extra levels take a third of the source's memory, in one buffer. ``lazy``: no
    level beyond 0 is built yet; :meth:`Pyramid.ensure` builds the rows footprints read.
    """
    shapes = [src.shape[:2]]
    while shapes[-1][0] >= 2 and shapes[-1][1] >= 2 and shapes[-1][0] % 2 == 0 and shapes[-1][1] % 2 == 0:
        shapes.append((shapes[-1][0] // 2, shapes[-1][1] // 2))
    nc = src.shape[2]
    sizes = [h * w * nc for h, w in shapes[1:]]
    offsets = np.concatenate([[0, 0], np.cumsum(sizes)[:-1]]).astype(np.int64)[:len(shapes)]
    rest = np.empty(max(1, sum(sizes)), np.float32)
    pyr = Pyramid(src.reshape(-1), rest, np.array(shapes, dtype=np.int64), offsets, nc, src,
                  [np.zeros(h, bool) for h, _ in shapes[1:]])
    if lazy:
        return pyr
    k = native.kernels()
    cur = c32(src)
    for lev, (h, w) in enumerate(shapes[1:], start=1):
        nxt = pyr.level(lev)
        step = -(-h // threads())  # rows of the level per thread (the kernel releases the GIL)
        run_bands(range(0, h, step), lambda r: k.halve(cur[2 * r:2 * (r + step)], nxt[r:r + step]))
        pyr.built[lev - 1][:] = True
        cur = nxt
    return pyr


def ensure_band(pyr: Pyramid, band):
    """Build the pyramid's rows that a footprint band reads (:meth:`Pyramid.ensure`): its samples' footprints,
    those split on the edge of the valid region left out, and the footprints of their sub-samples, each the
    sample's sides divided by the split. Returns what the filter reads: which samples (bool, as ``band.valid``),
    and the sub-samples' sides ((M, K, 4) float32)."""
    read = band.valid & ~band.edge
    pyr.ensure(band.ys, read, band.foot, getattr(band, "coarse", None))
    m, kk = band.edge_xs.shape
    sub = band.foot.reshape(-1, 4)[band.edge_idx] / np.float32(math.isqrt(kk))
    s64 = sub.astype(np.float64)
    # the split samples whose sub-samples may leave level 0 (a side beyond MAX_TAPS, or not a number): the others
    # read no coarser row
    far = np.flatnonzero(~((s64[:, 0] ** 2 + s64[:, 1] ** 2 <= MAX_TAPS ** 2)
                           & (s64[:, 2] ** 2 + s64[:, 3] ** 2 <= MAX_TAPS ** 2)))
    if len(far):
        pyr.ensure(band.edge_ys[far], band.edge_valid[far], np.broadcast_to(sub[far, None, :], (len(far), kk, 4)))
    return read, np.broadcast_to(sub[:, None, :], (m, kk, 4))


def sample_footprint(pyr: Pyramid, band, border: Border, out: np.ndarray,
                     alpha: np.ndarray) -> None:
    """Fill ``out`` and ``alpha`` for a footprint band (see the module docstring)."""
    wrap, top, bottom = border.flags
    read, sub = ensure_band(pyr, band)
    k = native.kernels()
    k.footprint(pyr.level0, pyr.rest, pyr.shapes, pyr.offsets, c32(band.xs), c32(band.ys),
                cbool(read), c32(band.foot), wrap, top, bottom, MAX_TAPS, out, alpha)
    if len(band.edge_idx):  # the samples split on the edge of the valid region: each valid sub-sample is
        # itself a footprint, its sample's sides divided by the split, so that it averages its own cell
        m = band.edge_xs.shape[0]
        ns = band.xs.shape[2]
        sub_out = np.empty((m, pyr.channels), np.float32)
        sub_alpha = np.empty(m, np.float32)
        k.footprint(pyr.level0, pyr.rest, pyr.shapes, pyr.offsets, c32(band.edge_xs), c32(band.edge_ys),
                    cbool(band.edge_valid), c32(sub), wrap, top, bottom, MAX_TAPS, sub_out, sub_alpha)
        pix = band.edge_idx // ns
        flat, flat_alpha = out.reshape(-1, pyr.channels), alpha.reshape(-1)
        np.add.at(flat, pix, sub_out * np.float32(1.0 / ns))
        np.add.at(flat_alpha, pix, sub_alpha * np.float32(1.0 / ns))
