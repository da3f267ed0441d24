"""The footprint prefilter's source side: a box-filtered pyramid of the source and the compiled
sampler that averages it over each output sample's footprint (see :mod:`lenslab.warp.antialias` for
the method and the footprints themselves). The sampler is C++ compiled ahead of time
(:mod:`lenslab.warp.kernels.native`, ``src/native/footprint.cpp``); :func:`lenslab.warp.kernels.reference.footprint` is
its NumPy reference."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from lenslab.warp.kernels import native
from lenslab.warp.kernels.dispatch import run_bands, threads
from lenslab.warp.kernels.native import c32, cbool
from lenslab.warp.seam import Border

MAX_TAPS = 8.0  # longest side of a footprint, in texels of the level it is read from (a coarser level
#               blurs: at 4 the error on forest.exr doubles; measured in docs/design.md)
WINDOW = 24  # texels: the side of the window of weights a footprint is gathered through (fits 2 MAX_TAPS + 3;
#              the same constant in src/native/footprint.cpp)
THIN = 1e-3  # texels: a footprint thinner than this (a line, a point) is given this thickness


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
    """Box-filtered levels of ``src`` (float32 H x W x C): level 0 is ``src``, each next one halves it (2x2
    mean, summed in float64: a finite source gives finite levels; compiled, one band of rows per thread).

    Halving stops at a level with an odd side (its seam or pole structure would shift by half a texel)
    or below 2 pixels. The extra levels take a third of the source's memory, in one buffer.
    """
    shapes = [src.shape[:2]]
    while shapes[-1][0] >= 2 and shapes[-1][1] >= 2 and shapes[-1][0] % 2 == 0 and shapes[-1][1] % 2 == 0:
        shapes.append((shapes[-1][0] // 2, shapes[-1][1] // 2))
    nc = src.shape[2]
    sizes = [h * w * nc for h, w in shapes[1:]]
    offsets = np.concatenate([[0, 0], np.cumsum(sizes)[:-1]]).astype(np.int64)[:len(shapes)]
    rest = np.empty(max(1, sum(sizes)), np.float32)
    k = native.kernels()
    cur = c32(src)
    for (h, w), off in zip(shapes[1:], offsets[1:]):
        nxt = rest[off:off + h * w * nc].reshape(h, w, nc)
        step = -(-h // threads())  # rows of the level per thread (the kernel releases the GIL)
        run_bands(range(0, h, step), lambda r: k.halve(cur[2 * r:2 * (r + step)], nxt[r:r + step]))
        cur = nxt
    return Pyramid(src.reshape(-1), rest, np.array(shapes, dtype=np.int64), offsets, nc, src)


def sample_footprint(pyr: Pyramid, band, border: Border, out: np.ndarray,
                     alpha: np.ndarray) -> None:
    """Fill ``out`` and ``alpha`` for a footprint band (see the module docstring)."""
    wrap, top, bottom = border.flags
    k = native.kernels()
    k.footprint(pyr.level0, pyr.rest, pyr.shapes, pyr.offsets, c32(band.xs), c32(band.ys),
                cbool(band.valid & ~band.edge), c32(band.foot), wrap, top, bottom, MAX_TAPS, out, alpha)
    if len(band.edge_idx):  # the samples split on the edge of the valid region: each valid sub-sample is
        # itself a footprint, its sample's sides divided by the split, so that it averages its own cell
        m, kk = band.edge_xs.shape
        ns = band.xs.shape[2]
        split = math.isqrt(kk)
        sub = band.foot.reshape(-1, 4)[band.edge_idx] / np.float32(split)
        sub_out = np.empty((m, pyr.channels), np.float32)
        sub_alpha = np.empty(m, np.float32)
        k.footprint(pyr.level0, pyr.rest, pyr.shapes, pyr.offsets, c32(band.edge_xs), c32(band.edge_ys),
                    cbool(band.edge_valid), c32(np.broadcast_to(sub[:, None, :], (m, kk, 4))), wrap, top, bottom,
                    MAX_TAPS, sub_out, sub_alpha)
        pix = band.edge_idx // ns
        flat, flat_alpha = out.reshape(-1, pyr.channels), alpha.reshape(-1)
        np.add.at(flat, pix, sub_out * np.float32(1.0 / ns))
        np.add.at(flat_alpha, pix, sub_alpha * np.float32(1.0 / ns))
