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


def source_window(bands: list[TapBand], src_width: int, src_height: int) -> tuple[int, int, int, int] | None:
    """``(row0, row1, col0, col1)``: the source pixels the taps of ``bands`` read (both taps of each pair), or
    None when a pixel goes through the folding sampler, which reads across the source's edges."""
    if any(len(b.fold_idx) for b in bands):
        return None
    r0, r1, c0, c1 = src_height, 0, src_width, 0
    for b in bands:
        off = b.off[b.off < FOLDED]
        if off.size:
            rows, cols = np.divmod(off, np.uint32(src_width))
            r0, r1 = min(r0, int(rows.min())), max(r1, int(rows.max()) + 2)
            c0, c1 = min(c0, int(cols.min())), max(c1, int(cols.max()) + 2)
    if r1 <= r0:
        return 0, 0, 0, 0
    return r0, min(r1, src_height), c0, min(c1, src_width)
