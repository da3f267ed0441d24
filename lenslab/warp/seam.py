"""Borders of a source image: what a filter tap outside the image, or outside its piece, reads.

The source lens says how its image continues (:meth:`~lenslab.lenses.core.base.Lens.seams` and
:meth:`~lenslab.lenses.core.base.Lens.pieces`); a tap beyond an edge is folded back in, so every filter
sees a continuous neighbourhood:

- an image with a period in x (a full-turn panorama) wraps horizontally: column ``-1`` is ``W-1``;
- beyond a pole edge the row ``-1 - j`` of column ``i`` is row ``j`` of column ``i + W/2`` (the
  opposite meridian; for odd ``W`` the half turn is rounded down to ``(W-1)/2`` columns, half a pixel
  short);
- a piecewise image whose pieces say what lies across their edges (cube faces) reads a tap that
  leaves the sample's piece from the neighbouring piece, the cube folded flat along their common edge
  (the tap ``k + 1/2`` px beyond the edge reads the pixel ``k + 1/2`` px inside the neighbour's edge),
  for every filter (pieces need whole-pixel rectangles; the footprint prefilter's coarser pyramid
  levels still average across pieces);
- every other border clamps to the edge pixel: a point that the lens maps inside the image but
  between its edge and the first pixel centre takes the edge value.

:func:`border_of` describes the border of a lens, :func:`fold_taps` and :func:`fold_piece` apply it to
taps (the compiled samplers fold theirs the same way), and :func:`pad` makes an explicitly padded copy for
code that wants plain arrays (``cv2.remap``, the mip pyramid of a small level).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from lenslab.warp.kernels import native


NO_PIECES = np.zeros((0, 16), dtype=np.int64)
NO_GRID = np.full((1, 1), -1, dtype=np.int64)


@dataclass(frozen=True, eq=False)
class Border:
    """How taps outside the source image (or outside their piece) are folded back in."""

    wrap: bool = False  # columns wrap (a full turn)
    pole_top: bool = False  # the top edge is a pole: reflect across it onto the opposite meridian
    pole_bottom: bool = False
    #: per piece: x0, y0, w, h, then (piece, edge, reversed) across its left, right, top, bottom edges
    #: (piece -1: nothing across); empty when the source has no piece topology
    pieces: np.ndarray = field(default_factory=lambda: NO_PIECES)
    #: the piece under each cell of a grid of ``cell`` = (width, height) pixels (-1: none)
    grid: np.ndarray = field(default_factory=lambda: NO_GRID)
    cell: tuple[int, int] = (1, 1)

    @property
    def flags(self) -> tuple[bool, bool, bool]:
        return self.wrap, self.pole_top, self.pole_bottom

    @property
    def has_pieces(self) -> bool:
        return len(self.pieces) > 0


def border_of(lens) -> Border:
    """The border rules of a source lens: its seams and, for pieces on a grid of whole pixels with
    neighbours across their edges, the piece table (see the module docstring)."""
    seams = lens.seams()
    if seams.wraps and seams.period_x != lens.width:
        raise ValueError(f"{lens.spec()}: a period of {seams.period_x} px is not the image width {lens.width}")
    table, grid, cell = piece_table(lens.pieces())
    return Border(seams.wraps, seams.pole_top and seams.wraps, seams.pole_bottom and seams.wraps, table, grid, cell)


def piece_table(pieces):
    """``(table, grid, cell)`` of :class:`Border` for ``pieces`` (empty unless they have neighbours and
    whole-pixel rectangles of one size on a grid)."""
    if len(pieces) < 2 or all(p.across is None for p in pieces):
        return NO_PIECES, NO_GRID, (1, 1)
    rects = np.array([p.rect for p in pieces], dtype=np.float64)
    cw, ch = rects[0, 2], rects[0, 3]
    whole = np.all(rects == np.round(rects)) and np.all(rects[:, 2] == cw) and np.all(rects[:, 3] == ch)
    if not whole or np.any(rects[:, 0] % cw) or np.any(rects[:, 1] % ch):
        return NO_PIECES, NO_GRID, (1, 1)
    table = np.full((len(pieces), 16), -1, dtype=np.int64)
    table[:, :4] = rects.astype(np.int64)
    for k, p in enumerate(pieces):
        for e, a in enumerate(p.across or (None,) * 4):
            if a is not None:
                table[k, 4 + 3 * e:7 + 3 * e] = (a.piece, a.edge, int(a.reversed))
    cols = int((rects[:, 0] // cw).max()) + 1
    rows = int((rects[:, 1] // ch).max()) + 1
    grid = np.full((rows, cols), -1, dtype=np.int64)
    grid[(rects[:, 1] // ch).astype(int), (rects[:, 0] // cw).astype(int)] = np.arange(len(pieces))
    return table, grid, (int(cw), int(ch))


def fold_piece(i: int, j: int, p: int, table: np.ndarray) -> tuple[int, int]:
    """Fold tap (column ``i``, row ``j``) of a sample in piece ``p`` into that piece or, beyond one of
    its edges, into the neighbour across it (the deeper of two edges for a corner tap); clamped into
    the piece where nothing lies across. ``table``: :attr:`Border.pieces`. The samplers fold their taps
    with the same compiled function (:mod:`lenslab.warp.kernels.native`)."""
    return native.kernels().fold_piece(int(i), int(j), int(p), np.ascontiguousarray(table, dtype=np.int64))


def fold_taps(i, j, w: int, h: int, wrap: bool, pole_top: bool, pole_bottom: bool) -> tuple[np.ndarray, np.ndarray]:
    """Fold taps (integer arrays: columns ``i``, rows ``j``) into ``0 <= i < w``, ``0 <= j < h`` by the
    border rules: across a pole onto the opposite meridian, wrapped at the seam, else clamped. The
    compiled samplers fold each tap the same way (``fold_index`` in ``src/native/kernels.h``)."""
    i = np.array(i, dtype=np.int64, copy=True)
    j = np.array(j, dtype=np.int64, copy=True)
    if pole_top:
        up = j < 0
        j[up] = -1 - j[up]
        i[up] += w // 2
    j = np.maximum(j, 0)
    if pole_bottom:
        down = j >= h
        j[down] = 2 * h - 1 - j[down]
        i[down] += w // 2
    j = np.clip(j, 0, h - 1)
    i = np.mod(i, w) if wrap else np.clip(i, 0, w - 1)
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
    fi, fj = fold_taps(ii, jj, w, h, *border.flags)
    return np.ascontiguousarray(image[fj, fi])
