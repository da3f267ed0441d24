"""The anti-aliasing footprint of an output made of parts of different sizes stays inside each part.

Facebook's split barrel (ffmpeg v360's ``barrelsplit``, 192x128 here) is two 128x64 equirect band
halves beside four 64x32 cap quarters; its map jumps at every part edge. A pixel beside such an edge
takes its footprint from its neighbour on the same side (one-sided differences), never from the pixel
across the edge. The expected footprints are v360's formulas transcribed here in float64, read
through a full-sphere equirect source (``phi = (2x/W - 1) pi``, ``theta = (1 - 2y/H) pi/2``).
"""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.lenses import Camera
from lenslab.warp.antialias import footprint_band, piece_numbers, piece_rects
from lenslab.warp.maps import Mapper

W, H = 192, 128  # the split barrel
SW, SH = 512, 256  # the equirect source
#: map positions are float32 source pixels (at most 512): their differences carry about 1e-4 px of
#: rounding; 1e-3 px is far below the fraction of a texel that changes a footprint's pyramid level
TOL = 1e-3


@pytest.fixture(scope="module")
def foot():
    src = Camera.from_spec("equirect", (SW, SH))
    dst = Camera.from_spec("fb-barrelsplit", (W, H))
    band = footprint_band(Mapper(src, dst), 0, H, np.array([[0.5, 0.5]]))
    return band.foot[:, :, 0].astype(np.float64)


def test_pieces_of_different_sizes_are_numbered_where_they_lie():
    rects = piece_rects(Camera.from_spec("fb-barrelsplit", (W, H)).lens)
    y, x = np.mgrid[0:H, 0:W] + 0.5
    k = piece_numbers(rects, x, y)
    want = np.where(x < 128, y // 64, 2 + y // 32)  # the band halves, then the cap quarters top to bottom
    np.testing.assert_array_equal(k, want)
    assert piece_numbers(rects, -0.5, 3.0) == -1


def test_band_footprint_is_the_equirect_scale_up_to_the_part_edges(foot):
    # band: phi = (3x/2W - 1/2 - b) pi, theta = (1/4 + b/2 - y/H) pi, so the source moves
    # (3 pi / 2W) SW / 2pi = 0.75 SW / W px per output column and (pi / H) SH / pi = SH / H px per row,
    # the same in the columns and rows beside the caps and the other half
    band = foot[:, :128]
    np.testing.assert_allclose(band[..., 0], 0.75 * SW / W, atol=TOL)
    np.testing.assert_allclose(band[..., 1], 0.0, atol=TOL)
    np.testing.assert_allclose(band[..., 2], 0.0, atol=TOL)
    np.testing.assert_allclose(band[..., 3], SH / H, atol=TOL)


def _top_cap_front(x, y):
    """Source pixel (continuous) of output pixel (x, y) in the first cap quarter: v360's
    ``(s - 1/2, -1/2, q/2)`` with ``s = 3x/W - 2``, ``q = 4y/H``, its y flipped to lenslab's frame (up)."""
    s, q = 3.0 * x / W - 2.0, 4.0 * y / H
    dx, dy, dz = s - 0.5, 0.5 + 0.0 * s, q / 2.0
    phi = np.arctan2(dx, dz)
    theta = np.arctan2(dy, np.hypot(dx, dz))
    return (phi / np.pi + 1.0) * SW / 2.0, (1.0 - 2.0 * theta / np.pi) * SH / 2.0


def test_cap_footprint_is_one_sided_at_the_quarter_edges(foot):
    # the lower half of the first quarter (rows 16..31, away from the pole): its left column borders
    # the band, its last row the next quarter; there the difference is one-sided, elsewhere central
    rows, cols = np.arange(16, 32), np.arange(128, 192)
    x, y = np.meshgrid(cols + 0.5, rows + 0.5, indexing="xy")
    lo_x = np.where(cols == 128, 0.0, 1.0)[None, :]  # no neighbour in the part beyond these
    hi_x = np.where(cols == 191, 0.0, 1.0)[None, :]
    hi_y = np.where(rows == 31, 0.0, 1.0)[:, None]
    want = []
    for (ex, ey), lo, hi in (((1.0, 0.0), lo_x, hi_x), ((0.0, 1.0), 1.0, hi_y)):
        xa, ya = _top_cap_front(x - lo * ex, y - lo * ey)
        xb, yb = _top_cap_front(x + hi * ex, y + hi * ey)
        want += [(xb - xa) / (lo + hi), (yb - ya) / (lo + hi)]
    got = foot[16:32, 128:192]
    for k in range(4):
        np.testing.assert_allclose(got[..., k], want[k], atol=TOL, err_msg=f"footprint component {k}")
