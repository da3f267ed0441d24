"""A cached map as taps: per output pixel, the flat index of its top-left source tap and the two
bilinear weights, made once when a plan keeps its maps (``WarpPlan(cache=True)``, every batch).

Each image warped through the plan then only reads and blends: no floor, no bounds test, no offset
arithmetic per pixel, which is what OpenCV's ``remap`` does after converting its maps to fixed point
(``convertMaps``); the weights here stay the exact float32 fractions, so the pixels are the same bits as
the single-tap sampler's (:func:`lenslab.warp.filters.sample`). A pixel whose 2x2 taps cross the
source's edge (the seam, a pole, the border) keeps its position and goes through the folding sampler.
Taps take 12 bytes a pixel against the map's 9; only one-sample bilinear maps of a source without
pieces and of fewer than 2^32 - 2 pixels become taps.
"""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np

from lenslab.warp.dispatch import kernel
from lenslab.warp.filters import lerp3, lerp_at, lerp_n

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
    off = np.empty(xs.shape, np.uint32)
    tx = np.empty(xs.shape, np.float32)
    ty = np.empty(xs.shape, np.float32)
    _taps_of(src_width, src_height, xs, ys, valid, off, tx, ty)
    fold = np.flatnonzero(off == FOLDED)
    return TapBand(band.r0, band.r1, off, tx, ty, fold, xs.reshape(-1)[fold].copy(), ys.reshape(-1)[fold].copy())


@numba.njit(cache=True, nogil=True)
def _taps_of(sw, sh, xs, ys, valid, off, tx, ty):
    h, w = xs.shape
    for r in range(h):
        for c in range(w):
            tx[r, c] = 0.0
            ty[r, c] = 0.0
            if not valid[r, c]:
                off[r, c] = INVALID
                continue
            x = xs[r, c]
            y = ys[r, c]
            fx0 = np.floor(x)
            fy0 = np.floor(y)
            i0 = np.int32(fx0)
            j0 = np.int32(fy0)
            if i0 >= 0 and j0 >= 0 and i0 + 1 < sw and j0 + 1 < sh:
                off[r, c] = np.uint32(j0 * sw + i0)
                tx[r, c] = x - fx0
                ty[r, c] = y - fy0
            else:
                off[r, c] = FOLDED


def sample_taps(src: np.ndarray, band: TapBand, border, out: np.ndarray, alpha: np.ndarray) -> None:
    """Fill ``out`` (h, W, C) and ``alpha`` (h, W) of a band from its taps."""
    sh, sw, nc = src.shape
    flat = src.reshape(-1)
    _from_taps(flat, sw, nc, band.off, band.tx, band.ty, out, alpha)
    if len(band.fold_idx):
        wrap, top, bottom = border.flags
        _folded(flat, sw, sh, nc, band.fold_idx, band.fold_x, band.fold_y, wrap, top, bottom, out, alpha)


@kernel.options(fastmath=True, error_model="numpy")
def _from_taps(flat, sw, nc, off, tx, ty, out, alpha):
    h, w = off.shape
    row = np.uint64(sw * nc)
    step = np.uint64(nc)
    for r in range(h):
        offr = off[r]
        txr = tx[r]
        tyr = ty[r]
        orow = out[r]
        arow = alpha[r]
        for c in range(w):
            o = offr[c]
            if o >= FOLDED:  # no source, or the folding sampler's
                if o == INVALID:
                    for ch in range(nc):
                        orow[c, ch] = 0.0
                    arow[c] = 0.0
                continue
            p00 = np.uint64(o) * step
            p01 = p00 + row
            fx = txr[c]
            fy = tyr[c]
            if nc == 3:  # written out: the compiler keeps the three channels in registers
                lerp3(flat, p00, p00 + step, p01, p01 + step, fx, fy, orow, c)
            else:
                lerp_n(flat, p00, p00 + step, p01, p01 + step, fx, fy, nc, orow, c)
            arow[c] = 1.0


@kernel.options(fastmath=True, error_model="numpy")
def _folded(flat, sw, sh, nc, idx, xs, ys, wrap, top, bottom, out, alpha):
    w = out.shape[1]
    for q in range(idx.shape[0]):
        r = idx[q] // w
        c = idx[q] % w
        lerp_at(flat, sw, sh, nc, xs[q], ys[q], wrap, top, bottom, out, r, c)
        alpha[r, c] = 1.0
