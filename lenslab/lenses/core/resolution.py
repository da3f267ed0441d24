"""A lens's angular resolution as a source (:meth:`~lenslab.lenses.core.base.Lens.pixels_per_degree`): the rows of
its first piece (a cube face, a tile, an eye, the whole image) over the angle they span down the piece's middle
column, the rows without rays (outside a fisheye's image circle, padding) left out.

That is the mean over the column: exact for a model whose rows are even in angle there (an equirect, an equidistant
fisheye, an equi-angular cube face), the mean of a perspective view's (whose pixels crowd in angle towards the
edges: a 90-degree view of 512 rows gives 512 / 90, where its centre has 256 px per radian, 4.47 per degree).
"""

from __future__ import annotations

import numpy as np

#: points down the column: the arc between neighbours is summed, so a model's curve is followed to ~1e-6 of its
#: length, and a column that crosses an image circle's edge loses at most 1/4096 of the rows
SAMPLES = 4097
#: pixels short of the piece's bottom edge where the column ends (an angle of ~1e-6 pixel's, far below a row's rounding)
BOTTOM_NUDGE = 1e-6


def column_pixels_per_degree(lens) -> float:
    """Rows over degrees down the middle column of ``lens``'s first piece, from its top edge to its bottom,
    counting only steps between two points with rays; the rows over 180 degrees when that column has none (a tile
    with no camera, an image of one row)."""
    return _line_pixels_per_degree(lens, across=False)


def row_pixels_per_degree(lens) -> float:
    """Columns over degrees along the middle row of ``lens``'s first piece, as :func:`column_pixels_per_degree`
    measures its column (a cylindrical panorama's width over its 360 degrees, where its column's mean is finer)."""
    return _line_pixels_per_degree(lens, across=True)


def _line_pixels_per_degree(lens, across: bool) -> float:
    piece = lens.pieces()[0]
    # one edge to the other, but for BOTTOM_NUDGE: a piece's far edge is the next piece's near one (a tile's, a face's)
    x0, y0, w, h = (piece.y0, piece.x0, piece.height, piece.width) if across else (piece.x0, piece.y0,
                                                                                  piece.width, piece.height)
    y = np.linspace(y0, y0 + h - BOTTOM_NUDGE, SAMPLES)
    xy = np.stack([np.full_like(y, x0 + 0.5 * w), y], axis=-1)
    d, ok = lens.pixel_to_dir(xy[..., ::-1] if across else xy)
    both = ok[1:] & ok[:-1]
    chord = np.linalg.norm(d[1:] - d[:-1], axis=-1)
    angle = np.degrees(2.0 * np.arcsin(np.clip(0.5 * chord[both], 0.0, 1.0))).sum()
    rows = float(np.diff(y)[both].sum())
    if not angle > 0.0:
        return (lens.width if across else lens.height) / 180.0
    return rows / angle
