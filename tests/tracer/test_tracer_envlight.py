"""Environment lights: lookups through lenslab's equirect lens, and importance sampling."""

from __future__ import annotations

import numpy as np
import pytest

import tracer
from lenslab.lenses import Camera
from tracer.envlight import ConstantEnvironment, EquirectEnvironment
from tracer.scene import merge_meshes


def _env_image(width=48, height=24, seed=0):
    rng = np.random.default_rng(seed)
    img = rng.uniform(0.0, 2.0, (height, width, 3)).astype(np.float32)
    img[3:5, 30:33] = 50.0
    return img


@pytest.mark.parametrize("yaw", [0.0, 90.0, -37.5])
def test_equirect_camera_sees_the_panorama_pixel_for_pixel(yaw):
    """Pixel centres of an equirect camera with the panorama's own size and pose land on its pixel centres."""
    img = _env_image()
    scene = merge_meshes([], environment=EquirectEnvironment(img, yaw=yaw))
    cam = Camera.from_spec("equirect", (img.shape[1], img.shape[0]), yaw=yaw)
    res = tracer.render(scene, cam, spp=1, seed=None)
    np.testing.assert_array_equal(res.image, img)


def test_hdr_panorama_from_file_round_trips(shared_data):
    path = shared_data / "hdri" / "studio.exr"
    env = EquirectEnvironment.from_file(path)
    scene = merge_meshes([], environment=env)
    cam = Camera.from_spec("equirect", (env.width, env.height))
    res = tracer.render(scene, cam, spp=1, seed=None)
    image, _ = __import__("lenslab.io", fromlist=["read"]).read(path)
    np.testing.assert_array_equal(res.image, np.maximum(np.nan_to_num(image[..., :3], posinf=0), 0))


def test_sampled_directions_follow_the_density():
    """A chi-square-like check: sample counts per panorama pixel match pmf * N."""
    img = _env_image(16, 8, seed=3)
    env = EquirectEnvironment(img)
    n = 200_000
    dirs, pdf = env.sample(np.random.default_rng(1).random((n, 2)))
    xy, ok = env.camera.world_to_pixel(dirs)
    assert ok.all()
    flat = np.clip(np.floor(xy[:, 1]).astype(int), 0, 7) * 16 + np.clip(np.floor(xy[:, 0]).astype(int), 0, 15)
    counts = np.bincount(flat, minlength=128)
    expected = env.pmf.ravel() * n
    # Poisson counts: every pixel within 5 standard deviations (sqrt of the expected count) plus one
    assert np.all(np.abs(counts - expected) <= 5 * np.sqrt(expected) + 1)
    np.testing.assert_allclose(pdf, env.pdf(dirs), rtol=1e-3)  # float32 directions near pixel edges


def test_constant_environment_is_uniform():
    env = ConstantEnvironment((1.0, 2.0, 3.0))
    d, pdf = env.sample(np.random.default_rng(0).random((1000, 2)))
    np.testing.assert_allclose(np.linalg.norm(d, axis=1), 1, rtol=1e-6)  # float32 unit vectors
    np.testing.assert_allclose(pdf, 1 / (4 * np.pi), rtol=1e-7)  # a float32 constant
    np.testing.assert_array_equal(env.eval(d), np.broadcast_to([1, 2, 3], (1000, 3)))
    with pytest.raises(ValueError):
        ConstantEnvironment(-1.0)
