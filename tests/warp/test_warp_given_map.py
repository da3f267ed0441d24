"""warp_with_map: any inverse map (an ST map, OpenCV's undistortion maps) applied with lenslab's filters,
checked against OpenCV's own remap and against analytic values."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from lenslab.errors import WarpError
from lenslab.lenses import Camera
from lenslab.warp import warp_with_map


def test_bilinear_matches_cv2_remap_at_its_own_sub_pixel_grid():
    rng = np.random.default_rng(3)
    img = rng.random((40, 60, 3)).astype(np.float32)
    # positions on OpenCV's 1/32-pixel grid (INTER_BITS = 5), where its fixed-point weights are exact,
    # kept inside the image so that no border rule is involved
    idx = np.round(rng.uniform([1, 1], [58, 38], size=(25, 35, 2)) * 32) / 32
    want = cv2.remap(img, idx[..., 0].astype(np.float32), idx[..., 1].astype(np.float32), cv2.INTER_LINEAR)
    got, alpha = warp_with_map(img, idx + 0.5)  # lenslab's coordinates put pixel centres at +0.5
    assert alpha.min() == 1.0
    # float32 arithmetic on values in [0, 1): a few ulps
    np.testing.assert_allclose(got, want, atol=2e-6)


def test_invalid_entries_are_empty_and_a_2d_image_stays_2d():
    img = np.full((10, 10), 3.0, dtype=np.float32)
    xy = np.full((4, 5, 2), 5.0)
    xy[1, 2] = np.nan
    valid = np.ones((4, 5), bool)
    valid[3, 4] = False
    out, alpha = warp_with_map(img, xy, valid, filter="lanczos")
    assert out.shape == (4, 5)
    assert out[1, 2] == 0 and alpha[1, 2] == 0 and out[3, 4] == 0 and alpha[3, 4] == 0
    assert out[0, 0] == 3.0 and alpha[0, 0] == 1.0  # Lanczos weights are normalised: a constant stays exact


def test_antialias_averages_a_ramp_over_the_footprint():
    # a map that shrinks a linear ramp 4x: the footprint average of a linear function is its value at
    # the footprint's centre, i = 4 x + 1.5 at output column x (centres of 4 source pixels)
    img = np.tile(np.arange(256, dtype=np.float32)[None, :, None], (8, 1, 1))
    x = (np.arange(64) + 0.5) * 4.0
    xy = np.stack(np.broadcast_arrays(x[None, :], np.full((4, 1), 4.0)), axis=-1)
    out, alpha = warp_with_map(img, xy, antialias=True)
    inner = out[:, 2:-2, 0]
    # float32 sums of weights that add to 1: 1e-4 relative
    np.testing.assert_allclose(inner, np.broadcast_to(4.0 * np.arange(2, 62) + 1.5, inner.shape), rtol=1e-4)


def test_a_panorama_source_wraps_at_its_seam():
    img = np.zeros((16, 32, 1), dtype=np.float32)
    img[:, 0] = 1.0  # the first column; the last one is 0
    xy = np.array([[[32.0, 8.5]]])  # on the seam: halfway between the last column's centre and the first's
    out, _ = warp_with_map(img, xy, source=Camera.from_spec("equirect", (32, 16)))
    assert out[0, 0, 0] == pytest.approx(0.5)  # the tent's weights at half a pixel, exact in float32
    out, _ = warp_with_map(img, xy)
    assert out[0, 0, 0] == 0.0  # without the lens, the tap clamps to the last column


def test_bad_maps_are_refused():
    with pytest.raises(WarpError, match="shape"):
        warp_with_map(np.zeros((4, 4)), np.zeros((4, 4)))
    with pytest.raises(WarpError, match="unknown filter"):
        warp_with_map(np.zeros((4, 4)), np.zeros((4, 4, 2)), filter="box")
