"""A lens maps one point as it maps an array of them: ``pixel_to_dir`` of shape ``(2,)`` and
``dir_to_pixel`` of shape ``(3,)`` give the first row of the ``(1, 2)`` / ``(1, 3)`` answer, for every
model (the API reference's examples look at single pixels), and the values are the conventions'."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.lenses import REGISTRY, make_lens

CASES = [case for name in sorted(REGISTRY) for case in REGISTRY[name].examples[:2]]


@pytest.mark.parametrize("spec,size", CASES, ids=[c[0] for c in CASES])
def test_one_point_is_the_first_row_of_an_array_of_one(spec, size):
    lens = make_lens(spec, size)
    xy = np.array([size[0] * 0.375 + 0.25, size[1] * 0.625 + 0.25])
    d, ok = lens.pixel_to_dir(xy)
    rows, oks = lens.pixel_to_dir(xy[None])
    assert d.shape == (3,) and np.ndim(ok) == 0
    np.testing.assert_array_equal(d, rows[0])
    assert bool(ok) == bool(oks[0])
    ray = np.array([0.3, -0.2, 0.9])
    p, seen = lens.dir_to_pixel(ray)
    prow, seens = lens.dir_to_pixel(ray[None])
    assert p.shape == (2,)
    np.testing.assert_array_equal(p, prow[0])
    assert bool(seen) == bool(seens[0])


def test_single_points_give_the_conventions_values():
    # lenslab's frame: +x right, +y up, +z forward (docs/conventions.md); pixel centres at k + 1/2
    d, ok = make_lens("equirect", (8, 4)).pixel_to_dir(np.array([4.0, 2.0]))  # the image's centre
    assert ok and np.array_equal(d, [0.0, 0.0, 1.0])
    # a 180-degree equidistant fisheye's rim, at the middle of the right edge, sees 90 degrees right
    d, ok = make_lens("fisheye:fov=180,mapping=equidistant", (64, 64)).pixel_to_dir(np.array([64.0, 32.0]))
    assert ok and np.allclose(d, [1.0, 0.0, 0.0], atol=1e-15)  # cos(pi/2) in float64 is 6e-17
    p, seen = make_lens("perspective:fov=90", (64, 48)).dir_to_pixel(np.array([1.0, 0.0, 1.0]))
    assert seen and np.allclose(p, [64.0, 24.0], atol=1e-12)  # 45 degrees right: the right edge
