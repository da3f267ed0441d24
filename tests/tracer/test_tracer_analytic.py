"""The tracer against radiance known in closed form.

Tolerances are statistical: a render's error is compared with its own standard error, estimated
from the per-pixel variance of the mean (pixels are independent, so the variance of the image mean
is the sum of the per-pixel variances over the pixel count squared). Fixed seeds make each check
deterministic; Z = 5 standard errors would be exceeded by chance about once in 1.7 million runs
per check for a correct renderer, while a bias of a few percent shows up as tens of sigmas.
"""

from __future__ import annotations

import numpy as np
import pytest

import tracer
from tracer import builtin
from tracer.envlight import EquirectEnvironment
from tracer.scene import merge_meshes

Z = 5.0  # standard errors allowed (see the module docstring)


def image_mean_and_se(result) -> tuple[np.ndarray, np.ndarray]:
    """Per-channel mean of the image and its standard error."""
    npix = result.image.shape[0] * result.image.shape[1]
    mean = result.image.reshape(-1, 3).mean(axis=0).astype(np.float64)
    se = np.sqrt(result.variance.reshape(-1, 3).astype(np.float64).sum(axis=0)) / npix
    return mean, se


def assert_close(result, expected, z=Z):
    mean, se = image_mean_and_se(result)
    assert np.all(np.isfinite(se)) and np.all(se > 0), "the renderer must report a finite, positive error"
    err = np.abs(mean - expected)
    assert np.all(err <= z * se), f"mean {mean} vs expected {expected}: {err / se} standard errors"


def rect_form_factor(a: float, b: float, h: float) -> float:
    """Point-to-rectangle form factor, rectangle a x b parallel at height h with one corner above the point."""
    x, y = a / h, b / h
    sx, sy = np.sqrt(1 + x * x), np.sqrt(1 + y * y)
    return (x / sx * np.arctan(y / sx) + y / sy * np.arctan(x / sy)) / (2 * np.pi)


def test_white_furnace_converges_to_le_over_one_minus_albedo():
    le, albedo = 1.0, 0.5
    scene = builtin.furnace(emission=le, albedo=albedo)
    res = tracer.render(scene, scene.camera(size=(8, 8)), spp=64, seed=3, max_depth=60)
    # 60 bounces leave out albedo^61 of the answer: far below the noise
    assert_close(res, le / (1 - albedo))


def test_furnace_energy_per_depth_is_the_geometric_series():
    le, albedo = 1.0, 0.5
    scene = builtin.furnace(emission=le, albedo=albedo)
    cam = scene.camera(size=(8, 8))
    means = []
    for depth in (0, 1, 2, 4):
        res = tracer.render(scene, cam, spp=32, seed=1, max_depth=depth)
        expected = le * (1 - albedo ** (depth + 1)) / (1 - albedo)
        if depth == 0:  # emission seen directly: exact, no noise at all
            np.testing.assert_allclose(res.image, expected, rtol=1e-6)  # float32 arithmetic
        else:
            assert_close(res, expected)
        means.append(res.image.mean())
    assert np.all(np.diff(means) > 0)


def test_diffuse_plane_under_uniform_sky_has_radiance_albedo_times_sky():
    albedo, sky = 0.4, 2.0
    scene = builtin.plane(albedo=albedo, radiance=sky)
    cam = scene.camera(size=(8, 8))
    for integrator in ("path", "direct"):
        res = tracer.render(scene, cam, spp=64, seed=5, integrator=integrator, max_depth=4)
        assert_close(res, albedo * sky)


def test_small_area_light_matches_the_analytic_irradiance():
    size, height, radiance, albedo = 0.2, 1.0, 10.0, 0.5
    scene = builtin.arealight(size=size, height=height, radiance=radiance, albedo=albedo)
    # the camera sees a 2-degree patch under the light's centre: the irradiance varies by ~1e-4
    # relative across it, far below the statistical tolerance
    cam = scene.camera(size=(9, 9))
    form_factor = 4 * rect_form_factor(size / 2, size / 2, height)
    expected = albedo * radiance * form_factor  # (albedo / pi) * (pi * radiance * F)
    for integrator in ("path", "direct"):
        res = tracer.render(scene, cam, spp=64, seed=2, integrator=integrator, max_depth=3)
        assert_close(res, expected)


def test_point_light_direct_render_is_exact_and_noise_free():
    """Inverse-square law: a point light of intensity I at height h over a Lambertian floor."""
    from tracer.materials import Material
    from tracer.scene import PointLight, View

    h, intensity, albedo = 2.0, 3.0, 0.6
    floor = builtin.quad([(-5, 0, -5), (5, 0, -5), (5, 0, 5), (-5, 0, 5)], facing=(0, 1, 0)) + (Material("f", kd=albedo),)
    scene = merge_meshes([floor], point_lights=[PointLight((0, h, 0), intensity)],
                         views={"default": View(eye=(0, 1, 0), look_at=(0, 0, 0), up=(0, 0, 1), lens="perspective:fov=0.5")})
    res = tracer.render(scene, scene.camera(size=(3, 3)), spp=4, seed=None, integrator="direct")
    # floor radiance (albedo / pi) * I / h^2 directly below; the 0.5 degree view spans ~1e-5 relative change
    np.testing.assert_allclose(res.image, albedo / np.pi * intensity / h**2, rtol=1e-4)
    # the only spread between a pixel's samples is the true variation of radiance across the pixel
    assert np.all(res.variance <= (1e-4 * res.image) ** 2)
    again = tracer.render(scene, scene.camera(size=(3, 3)), spp=4, seed=None, integrator="direct")
    np.testing.assert_array_equal(again.image, res.image)


def _synthetic_env(width=64, height=32) -> np.ndarray:
    rng = np.random.default_rng(7)
    img = rng.uniform(0.2, 1.0, (height, width, 3)).astype(np.float32)
    img[4:7, 40:44] = (40.0, 30.0, 20.0)  # a small bright sun high in the sky
    return img


def test_environment_pdf_is_normalised_and_matches_its_samples():
    env = EquirectEnvironment(_synthetic_env(), yaw=30.0)
    rng = np.random.default_rng(0)
    d = rng.normal(size=(200_000, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    integral = env.pdf(d).astype(np.float64).mean() * 4 * np.pi
    # Monte Carlo integral of the density over the sphere with uniform directions: 200k samples of a
    # density peaking ~50x its mean give a standard error near 1%
    assert abs(integral - 1.0) < 0.05
    dirs, pdf = env.sample(rng.random((1000, 2)))
    np.testing.assert_allclose(pdf, env.pdf(dirs), rtol=1e-3)  # float32 directions at pixel edges


def test_diffuse_plane_under_hdr_environment_matches_exact_irradiance():
    img = _synthetic_env()
    env = EquirectEnvironment(img)
    h, w = img.shape[:2]
    # exact irradiance on an upward plane from a piecewise-constant panorama: per pixel row,
    # integral of sin(lat) cos(lat) dlat dlon = dlon * (sin^2(top) - sin^2(bottom)) / 2 (upper half only)
    lat_edges = np.pi / 2 - np.arange(h + 1) * np.pi / h
    s2 = np.sin(np.clip(lat_edges, 0, None)) ** 2
    row_w = (s2[:-1] - s2[1:]) / 2 * (2 * np.pi / w)
    irradiance = (img.astype(np.float64) * row_w[:, None, None]).sum(axis=(0, 1))
    albedo = 0.5
    scene = builtin.plane(albedo=albedo)
    scene.environment = env
    res = tracer.render(scene, scene.camera(size=(8, 8)), spp=64, seed=4, max_depth=2)
    assert_close(res, albedo / np.pi * irradiance)


def test_direct_and_path_agree_at_depth_one():
    scene = tracer.load_scene("cornell")
    cam = scene.camera(size=(24, 24))
    a = tracer.render(scene, cam, spp=32, seed=1, integrator="path", max_depth=1)
    b = tracer.render(scene, cam, spp=32, seed=2, integrator="direct")
    (ma, sa), (mb, sb) = image_mean_and_se(a), image_mean_and_se(b)
    assert np.all(np.abs(ma - mb) <= Z * np.hypot(sa, sb)), (ma, mb, sa, sb)


def test_path_energy_increases_with_depth_and_converges():
    scene = tracer.load_scene("cornell")
    cam = scene.camera(size=(16, 16))
    means = [tracer.render(scene, cam, spp=8, seed=0, max_depth=k).image.mean() for k in (1, 2, 3, 4, 6, 10)]
    steps = np.diff(means)
    # the same seed replays the same first bounces, so a deeper render only adds light: strictly
    assert np.all(steps > 0), means
    # ...and each extra bounce adds less (the box reflects well under half the light)
    assert steps[0] > steps[1] > steps[2] > 0
    assert steps[-1] < 0.05 * means[-1]


@pytest.mark.parametrize("seed", [0, 1])
def test_mirror_reflects_ks_times_what_it_sees(seed):
    """A mirror plane under a uniform sky, seen from above: radiance ks * sky, exactly, in any integrator."""
    from tracer.envlight import ConstantEnvironment
    from tracer.materials import Material
    from tracer.scene import View

    mirror = Material("m", kind="mirror", kd=0.0, ks=(0.9, 0.5, 0.2))
    part = builtin.quad([(-1, 0, -1), (1, 0, -1), (1, 0, 1), (-1, 0, 1)]) + (mirror,)
    scene = merge_meshes([part], environment=ConstantEnvironment(2.0),
                         views={"default": View(eye=(0, 1, 0.2), look_at=(0, 0, 0), lens="perspective:fov=30")})
    for integrator in ("path", "direct"):
        res = tracer.render(scene, scene.camera(size=(6, 6)), spp=4, seed=seed, integrator=integrator, max_depth=3)
        np.testing.assert_allclose(res.image, np.broadcast_to([1.8, 1.0, 0.4], res.image.shape), rtol=1e-5)


def test_scene_far_from_the_world_origin_renders_the_same():
    """Geometry 30 km from the origin: float32 world coordinates would be 2 mm coarse there; the tracer
    works relative to the scene centre, so the furnace still converges to Le / (1 - a)."""
    from tracer.materials import Material
    from tracer.scene import View

    centre = np.array([1e4, -2e4, 2e4])
    mat = Material("furnace", kd=0.5, emission=1.0)
    scene = merge_meshes([builtin.sphere_mesh(tuple(centre), 1.0, 16, inward=True) + (mat,)],
                         views={"default": View(eye=tuple(centre), look_at=tuple(centre + [0, 0, 1]),
                                                lens="perspective:fov=90")})
    res = tracer.render(scene, scene.camera(size=(8, 8)), spp=64, seed=3, max_depth=60)
    assert_close(res, 2.0)


def test_direct_and_path_agree_at_depth_one_with_glossy_surfaces_and_an_hdr_sky():
    """MIS with a Phong lobe and an importance-sampled panorama: the same direct light as light sampling alone."""
    from tracer.materials import Material
    from tracer.scene import View

    glossy = Material("g", kind="glossy", kd=(0.3, 0.2, 0.1), ks=(0.5, 0.5, 0.5), exponent=30.0)
    ground = Material("ground", kd=0.5)
    parts = [builtin.quad([(-3, 0, -3), (3, 0, -3), (3, 0, 3), (-3, 0, 3)], facing=(0, 1, 0)) + (ground,),
             builtin.sphere_mesh((0.0, 0.5, 0.0), 0.5, 24) + (glossy,)]
    scene = merge_meshes(parts, environment=EquirectEnvironment(_synthetic_env(), yaw=40.0),
                         views={"default": View(eye=(0, 0.9, -1.6), look_at=(0, 0.4, 0), lens="perspective:fov=50")})
    cam = scene.camera(size=(16, 16))
    a = tracer.render(scene, cam, spp=32, seed=1, integrator="path", max_depth=1)
    b = tracer.render(scene, cam, spp=32, seed=2, integrator="direct")
    (ma, sa), (mb, sb) = image_mean_and_se(a), image_mean_and_se(b)
    assert np.all(np.abs(ma - mb) <= Z * np.hypot(sa, sb)), (ma, mb, sa, sb)
