"""Borders of a source image: the equirect seam wraps, a row across a pole continues on the opposite meridian.

A filter tap that falls outside the source image is folded back in, so every filter sees a
continuous neighbourhood:

- a full-turn equirect (``lon_max - lon_min = 360``) wraps horizontally: column ``-1`` is column ``W-1``;
- at a pole (``lat_max = 90`` or ``lat_min = -90`` on a full-turn equirect) the row above the top row is
  the top row itself on the opposite meridian, half a turn away: row ``-1 - j`` of column ``i`` is
  row ``j`` of column ``i + W/2`` (for odd ``W`` the half turn is rounded down to ``(W-1)/2`` columns,
  half a pixel short);
- every other border (perspective, fisheye, partial equirect...) clamps to the edge pixel: a point that
  the lens maps inside the image but between its edge and the first pixel centre takes the edge value.

A cube-map or tiled *source* is folded at the edges of the whole image only: inside it, the filters
see one image, so a sample within the outer half pixel of a face reads the adjacent pixels of the
layout, which belong to another face (or tile) and generally show another direction. The reach is
the filter's support beyond the face edge: 1/2 px of interpolation for ``bilinear`` (the taps of the
pixel across the seam), 1.5 px for ``bicubic``, 2.5 px for ``lanczos``, and with ``antialias`` half the
footprint plus one texel of the pyramid level read (deeper levels average across faces). Pixels of
the output that see a source face's outermost pixel row or column are affected; convert such a source
to equirect first (``lenslab warp --to equirect``) when that matters.

:func:`border_of` describes the border of a lens, :func:`fold_index` applies it to one tap (compiled, used
by the samplers), and :func:`pad` makes an explicitly padded copy for code that wants plain arrays
(``cv2.remap``, the mip pyramid of a small level).
"""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np


@dataclass(frozen=True)
class Border:
    """How taps outside the source image are folded back in."""

    wrap: bool = False  # columns wrap (full-turn equirect)
    pole_top: bool = False  # the top edge is a pole: reflect across it onto the opposite meridian
    pole_bottom: bool = False

    @property
    def flags(self) -> tuple[bool, bool, bool]:
        return self.wrap, self.pole_top, self.pole_bottom


def border_of(lens) -> Border:
    """The border rules of a source lens (see the module docstring)."""
    if getattr(lens, "name", "") == "equirect" and getattr(lens, "wraps", False):
        return Border(True, lens.lat_max == 90.0, lens.lat_min == -90.0)
    return Border()


@numba.njit(inline="always", cache=True)
def fold_index(i, j, w, h, wrap, pole_top, pole_bottom):
    """Fold tap (column ``i``, row ``j``) into ``0 <= i < w``, ``0 <= j < h`` by the border rules."""
    if j < 0:
        if pole_top:
            j = -1 - j
            i += w // 2
        if j < 0:
            j = 0
    if j >= h:
        if pole_bottom:
            j = 2 * h - 1 - j
            i += w // 2
        if j >= h:
            j = h - 1
        if j < 0:  # a kernel taller than a tiny image: stay inside
            j = 0
    if wrap:
        i = i % w
    elif i < 0:
        i = 0
    elif i >= w:
        i = w - 1
    return i, j


def pad(image: np.ndarray, border: Border, n: int) -> np.ndarray:
    """A copy of ``image`` (H x W x C) with ``n`` pixels added on every side by the border rules.

    Used where a plain array is needed (e.g. ``cv2.remap`` with ``BORDER_CONSTANT`` sees the right
    neighbours across the seam and the poles); shift sample coordinates by ``n``.
    """
    h, w = image.shape[:2]
    rows = np.arange(-n, h + n)
    cols = np.arange(-n, w + n)
    jj, ii = np.meshgrid(rows, cols, indexing="ij")
    fi, fj = _fold_grid(ii.astype(np.int64), jj.astype(np.int64), w, h, *border.flags)
    return np.ascontiguousarray(image[fj, fi])


@numba.njit(cache=True)
def _fold_grid(ii, jj, w, h, wrap, pole_top, pole_bottom):
    oi = np.empty_like(ii)
    oj = np.empty_like(jj)
    for a in range(ii.shape[0]):
        for b in range(ii.shape[1]):
            oi[a, b], oj[a, b] = fold_index(ii[a, b], jj[a, b], w, h, wrap, pole_top, pole_bottom)
    return oi, oj
