"""The bench's independent accuracy reference reads what the formulas say: a pixel centre's ray reads that
pixel, a constant panorama gives the constant times the fisheye's coverage."""

from __future__ import annotations

import numpy as np

from lenslab.bench.warp_reference import bilinear_equirect, reference


def test_the_ray_of_a_pixel_centre_reads_that_pixel_and_rows_fold_across_the_poles():
    rng = np.random.default_rng(0)
    img = rng.random((8, 16, 3))
    # centre of pixel (i, j): longitude (2 (i + 1/2) / 16 - 1) pi, latitude (1 - 2 (j + 1/2) / 8) pi/2
    i, j = 5, 2
    lon, lat = (2 * (i + 0.5) / 16 - 1) * np.pi, (1 - 2 * (j + 0.5) / 8) * np.pi / 2
    d = np.array([np.cos(lat) * np.sin(lon), np.sin(lat), np.cos(lat) * np.cos(lon)])
    np.testing.assert_allclose(bilinear_equirect(img, d), img[j, i], rtol=1e-12)
    # the north pole itself (longitude atan2(0, 0) = 0: x index W/2 - 1/2, between columns 7 and 8; y
    # index -1/2, halfway between row 0 and its mirror across the pole, half a turn away): weights 1/4
    pole = bilinear_equirect(img, np.array([0.0, 1.0, 0.0]))
    want = 0.25 * (img[0, 7] + img[0, 8] + img[0, 15] + img[0, 0])
    np.testing.assert_allclose(pole, want, rtol=1e-12)


def test_a_constant_panorama_gives_the_constant_times_the_coverage():
    img = np.full((32, 64, 3), 2.5)
    ref = reference(img, 16, 180.0, k=8)
    np.testing.assert_allclose(ref[8, 8], 2.5)  # inside the circle: every stratum sees the sphere
    assert np.all(ref[0, 0] == 0.0)  # the corner lies outside the circle (r > 1 for all strata)
    # the total is the constant times the circle's area pi (W/2)^2 in pixels, to the strata's resolution
    assert abs(ref[..., 0].sum() / 2.5 - np.pi * 64) < 0.02 * np.pi * 64  # edge strata: ~1% of the area
