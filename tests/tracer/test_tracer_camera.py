"""The tracer's rays come from lenslab's lens objects: one model of every lens, shared with the warp engine.

A pixel of any lens model that looks in the same direction as an equirect pixel must see the same
radiance. The lit point-light Cornell box with direct lighting and pixel-centre samples is
deterministic, so those comparisons are exact up to float32 rounding of nearby directions.
"""

from __future__ import annotations

import numpy as np
import pytest

import tracer
from lenslab.lenses import REGISTRY, Camera, Pose, make_lens
from lenslab.errors import LensError

EYE = (0.2, 0.25, 0.25)  # inside the box, looking at the back wall and the tall block


@pytest.fixture(scope="module")
def scene():
    return tracer.load_scene("cornell-point")


@pytest.fixture(scope="module")
def panorama(scene):
    cam = Camera.from_spec("equirect", (64, 32), eye=EYE)
    return cam, tracer.render(scene, cam, spp=1, seed=None, integrator="direct")


def _equirect_pixel(panorama, x, y):
    cam, res = panorama
    d = cam.pixel_to_world(np.array([[x + 0.5, y + 0.5]]))[1][0]
    return d, res.image[y, x]


def test_fisheye_centre_pixel_sees_what_the_equirect_pixel_sees(scene, panorama):
    for x, y in [(35, 14), (30, 17), (40, 12)]:  # back wall, floor, ceiling near the light
        d, expected = _equirect_pixel(panorama, x, y)
        eye = np.asarray(EYE)
        cam = Camera.from_spec("fisheye:fov=180,mapping=equisolid", (33, 33), eye=EYE, look_at=eye + d)
        res = tracer.render(scene, cam, spp=1, seed=None, integrator="direct")
        # identical directions up to float64 rounding: the same float32 radiance to 1e-4 relative
        np.testing.assert_allclose(res.image[16, 16], expected, rtol=1e-4, atol=1e-7)


def test_every_registered_lens_pixel_sees_the_equirect_radiance(scene, panorama):
    d, expected = _equirect_pixel(panorama, 35, 14)
    eye = np.asarray(EYE)
    checked = []
    for name in sorted(REGISTRY):
        try:
            lens = make_lens(name, (24, 24))
        except LensError:  # a model that needs parameters to exist at all
            continue
        cam = Camera(lens, Pose.look_at(eye, eye + d))
        xy, ok = cam.world_to_pixel(d[None])
        if not ok[0]:
            continue
        xy_back, d_back, ok_back = cam.pixel_to_world(xy)
        if not ok_back[0] or np.dot(d_back[0], d) < 1 - 1e-9:  # the model's inverse does not return here
            continue
        got, _, valid = tracer.trace_pixels(scene, cam, xy, spp=1, seed=None, integrator="direct")
        assert valid[0]
        # a round trip through the model's inverse moves the direction by float64 rounding: same radiance
        # to float32 precision of the shading arithmetic (1e-4 relative)
        np.testing.assert_allclose(got[0], expected, rtol=1e-4, atol=1e-7, err_msg=name)
        checked.append(name)
    assert {"perspective", "equirect", "fisheye"} <= set(checked), checked


def test_path_traced_fisheye_and_equirect_pixels_agree_statistically():
    scene = tracer.load_scene("cornell")
    pano = Camera.from_spec("equirect", (64, 32), eye=EYE)
    xy = np.array([[35.5, 14.5]])
    d = pano.pixel_to_world(xy)[1][0]
    fish = Camera.from_spec("fisheye:fov=120", (33, 33), eye=EYE, look_at=np.asarray(EYE) + d)
    a, va, _ = tracer.trace_pixels(scene, pano, xy, spp=400, seed=1, max_depth=4)
    b, vb, _ = tracer.trace_pixels(scene, fish, [[16.5, 16.5]], spp=400, seed=2, max_depth=4)
    # independent estimates of the same radiance: within 5 standard errors of their difference
    assert np.all(np.abs(a - b) <= 5 * np.sqrt(va + vb)), (a, b, va, vb)


def test_tiled_views_trace_from_each_tiles_own_eye(scene):
    base = np.asarray(EYE)
    tiles = [
        {"lens": "perspective:fov=70", "eye": [-0.08, 0.0, 0.0]},
        {"lens": "fisheye:fov=150", "eye": [0.08, 0.02, 0.0], "yaw": 15.0},
    ]
    tiled = Camera(make_lens({"model": "tiled", "grid": "2x1", "tiles": tiles}, (32, 16)), Pose(eye=base))
    res = tracer.render(scene, tiled, spp=1, seed=None, integrator="direct")
    for k, t in enumerate(tiles):
        single = Camera.from_spec(t["lens"], (16, 16), yaw=t.get("yaw", 0.0), eye=base + np.asarray(t["eye"]))
        ref = tracer.render(scene, single, spp=1, seed=None, integrator="direct")
        # the same rays (tile offsets composed in float64), the same deterministic shading: float32 rounding only
        np.testing.assert_allclose(res.image[:, 16 * k:16 * (k + 1)], ref.image, rtol=1e-4, atol=1e-6)


def test_pixels_outside_a_lens_are_transparent(scene):
    cam = Camera.from_spec("fisheye:fov=180", (16, 16), eye=EYE)
    res = tracer.render(scene, cam, spp=4, seed=0, integrator="direct")
    xy = cam.pixel_grid(samples=1, seed=None)[:, :, 0]
    inside = cam.lens.pixel_to_dir(xy)[1]
    assert np.all(res.alpha[inside] > 0)
    corner = (slice(0, 2), slice(0, 2))
    assert np.all(res.alpha[corner] == 0) and np.all(res.image[corner] == 0)
