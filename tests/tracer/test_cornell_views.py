"""The Cornell box's views: the published camera, and the default that stands in the box's opening.

Values from the Cornell box data (http://www.graphics.cornell.edu/online/box/data.html): camera at
(278, 273, -800) mm looking along +z, 35 mm focal length on 25 x 25 mm film; the box's open front is
the plane z = 0 (in lenslab's frame x is mirrored, x -> 556 - x, which keeps 278 at 278).
"""

from __future__ import annotations

import numpy as np
import pytest

from tracer import load_scene


@pytest.fixture(scope="module")
def cornell():
    return load_scene("cornell")


def test_the_published_camera(cornell):
    v = cornell.views["published"]
    np.testing.assert_allclose(v.eye, (0.278, 0.273, -0.800), atol=1e-12)  # mm -> m, exact in float64
    np.testing.assert_allclose(np.subtract(v.look_at, v.eye), (0, 0, 1), atol=1e-12)
    fov = float(v.lens.partition("fov=")[2])
    assert fov == pytest.approx(2 * np.degrees(np.arctan(12.5 / 35.0)), abs=1e-4)  # 39.3077 deg, 4 decimals


def test_the_default_view_stands_in_the_opening_and_a_fisheye_sees_only_the_box(cornell):
    v = cornell.views["default"]
    np.testing.assert_allclose(v.eye, (0.278, 0.273, 0.001), atol=1e-12)  # 1 mm inside the front plane z = 0
    np.testing.assert_allclose(np.subtract(v.look_at, v.eye), (0, 0, 1), atol=1e-12)
    cam = cornell.camera("fisheye:fov=180,mapping=equisolid", (48, 48))
    gx, gy = np.meshgrid(np.arange(48) + 0.5, np.arange(48) + 0.5)
    origins, dirs, valid = cam.pixel_to_world(np.stack([gx, gy], axis=-1))
    o, d = origins[valid], dirs[valid]
    shift = np.asarray(getattr(cornell, "shift", np.zeros(3)))
    if np.any(np.asarray(getattr(cornell.accel, "shift", np.zeros(3)))):
        shift = np.zeros(3)  # the accelerator shifts world points itself
    prim, _ = cornell.accel.intersect(o - shift, d)
    assert valid.sum() > 0.75 * 48 * 48  # the image circle: pi/4 of the square
    assert (prim >= 0).all()  # every ray of the fisheye hits a wall, the floor, the ceiling or a block
    # the published camera, by contrast, sees mostly the outside through a 180-degree fisheye
    far = cornell.camera("fisheye:fov=180,mapping=equisolid", (48, 48), view="published")
    o, d, ok = far.pixel_to_world(np.stack([gx, gy], axis=-1))
    prim, _ = cornell.accel.intersect(o[ok] - shift, d[ok])
    assert (prim < 0).mean() > 0.5
