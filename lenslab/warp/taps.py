"""A cached map as taps: per output pixel, the flat index of its top-left source tap and the two
bilinear weights, made once when a plan keeps its maps (``WarpPlan(cache=True)``, every batch).

Each image warped through the plan then only reads and blends: no floor, no bounds test, no offset
arithmetic per pixel, which is what OpenCV's ``remap`` does after converting its maps to fixed point
(``convertMaps``); the weights here stay the exact float32 fractions, so the pixels are the same bits as
the single-tap sampler's (:func:`lenslab.warp.filters.sample`); compiled ahead of time
(:mod:`lenslab.warp.kernels.native`). A pixel whose 2x2 taps cross the
source's edge (the seam, a pole, the border) keeps its position and goes through the folding sampler.
Taps take 12 bytes a pixel against the map's 9; only one-sample bilinear maps of a source without
pieces and of fewer than 2^32 - 2 pixels become taps.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from lenslab.warp.kernels import native
from lenslab.warp.kernels.native import c32, cbool

INVALID = np.uint32(0xFFFFFFFF)  # no source: colour and alpha 0
FOLDED = np.uint32(0xFFFFFFFE)  # taps across an edge: the folding sampler


@dataclass
class TapBand:
    r0: int
    r1: int
    off: np.ndarray  # (h, W) uint32: j * width + i of the top-left tap, or INVALID / FOLDED
    tx: np.ndarray  # (h, W) float32: x - floor(x)
    ty: np.ndarray  # (h, W) float32
    fold_idx: np.ndarray  # (m,) int64: flat indices (into h x W) of the FOLDED pixels
    fold_x: np.ndarray  # (m,) float32: their source index coordinates
    fold_y: np.ndarray

    @property
    def nbytes(self) -> int:
        return sum(a.nbytes for a in (self.off, self.tx, self.ty, self.fold_idx, self.fold_x, self.fold_y))


def eligible(filter: str, samples: int, border, src_pixels: int) -> bool:
    """Whether a cached band of this plan becomes taps."""
    return filter == "bilinear" and samples == 1 and not border.has_pieces and src_pixels < int(FOLDED)


def taps_of(band, src_width: int, src_height: int) -> TapBand:
    """The taps of a one-sample map band (:class:`lenslab.warp.maps.MapBand`)."""
    xs, ys, valid = band.xs[..., 0], band.ys[..., 0], band.valid[..., 0]
    xs, ys, valid = c32(xs), c32(ys), cbool(valid)
    off = np.empty(xs.shape, np.uint32)
    tx = np.empty(xs.shape, np.float32)
    ty = np.empty(xs.shape, np.float32)
    native.kernels().taps_of(src_width, src_height, xs, ys, valid, off, tx, ty)
    fold = np.flatnonzero(off == FOLDED)
    return TapBand(band.r0, band.r1, off, tx, ty, fold, xs.reshape(-1)[fold].copy(), ys.reshape(-1)[fold].copy())


def sample_taps(src: np.ndarray, band: TapBand, border, out: np.ndarray, alpha: np.ndarray) -> None:
    """Fill ``out`` (h, W, C) and ``alpha`` (h, W) of a band from its taps."""
    sh, sw, nc = src.shape
    flat = src.reshape(-1)
    k = native.kernels()
    k.from_taps(flat, sw, nc, band.off, band.tx, band.ty, out, alpha)
    if len(band.fold_idx):
        wrap, top, bottom = border.flags
        k.folded(flat, sw, sh, nc, band.fold_idx, band.fold_x, band.fold_y, wrap, top, bottom, out, alpha)


def source_spans(bands: list[TapBand], border, src_width: int, src_height: int) -> np.ndarray:
    """The source pixels the taps of ``bands`` read, all four taps of each pixel, those of the folding sampler
    (across the seam, over a pole) included: ``(src_height, 4)`` int64, row ``j`` read within columns
    ``spans[j, 0]`` to ``spans[j, 1] - 1`` and ``spans[j, 2]`` to ``spans[j, 3] - 1`` (the second span empty but
    where the row is read on both sides of the seam; all 0 for a row not read). No other source pixel is read."""
    read = np.zeros((src_height, src_width), np.uint8)
    wrap, top, bottom = border.flags
    k = native.kernels()
    for b in bands:
        k.tap_reads(src_width, src_height, b.off.reshape(-1), b.fold_x, b.fold_y, wrap, top, bottom, read)
    spans = np.empty((src_height, 4), np.int64)
    k.read_spans(src_width, src_height, read, spans)
    return spans


def source_window(spans: np.ndarray) -> tuple[int, int, int, int]:
    """``(row0, row1, col0, col1)``: the box around :func:`source_spans`'s ``spans`` (all 0 when nothing is read)."""
    some = (spans[:, 1] > spans[:, 0]) | (spans[:, 3] > spans[:, 2])
    rows = np.flatnonzero(some)
    if not rows.size:
        return 0, 0, 0, 0
    lo = np.where(spans[rows, 1] > spans[rows, 0], spans[rows, 0], spans[rows, 2])
    hi = np.where(spans[rows, 3] > spans[rows, 2], spans[rows, 3], spans[rows, 1])
    return int(rows[0]), int(rows[-1]) + 1, int(lo.min()), int(hi.max())
