"""A stereo frame's pinned points in its second eye.

The conformance suite checks each stereo reference point (a base model's point pinned from outside
lenslab, in the left or top eye) both ways. A direction maps to the first eye only, so the second eye's
copy of the point holds one way: the pixel shifted by one eye (right half for ``sbs``, bottom half for
``tb``) sees the pinned direction, to the point's own tolerance in pixels, as in the conformance suite.
"""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.lenses import REGISTRY, make_lens

POINTS = REGISTRY.entry("stereo").capabilities["reference_points"]


def angle(a, b) -> float:
    """The angle between two directions, exact near 0."""
    return float(np.arctan2(np.linalg.norm(np.cross(a, b)), a @ b))


@pytest.mark.parametrize("point", POINTS, ids=[p.spec for p in POINTS])
def test_the_second_eye_sees_the_pinned_direction(point):
    lens = make_lens(point.spec, point.size)
    shift = (lens.eye_size[0], 0.0) if lens.layout == "sbs" else (0.0, lens.eye_size[1])
    pixel = np.add(point.pixel, shift)
    d, ok = lens.pixel_to_dir(np.array([pixel, pixel + (0.5, 0.0)]))
    assert ok[0], point.source
    per_px = 2.0 * angle(d[0], d[1])  # the angle of one pixel step there
    assert angle(d[0], np.asarray(point.direction)) <= point.tolerance * per_px + 1e-15, (d[0], point.direction)


@pytest.mark.parametrize("point", POINTS, ids=[p.spec for p in POINTS])
def test_a_direction_is_found_in_the_first_eye(point):
    lens = make_lens(point.spec, point.size)
    xy, ok = lens.dir_to_pixel(np.array([point.direction]))
    assert ok[0] and np.abs(xy[0] - point.pixel).max() <= point.tolerance
    assert xy[0, 0] < lens.eye_size[0] and xy[0, 1] < lens.eye_size[1]
