"""The compiled bounce loop (tracer.wavefront) against the NumPy steps of tracer.integrators it replaces.

The NumPy steps are the reference: both draw the same random numbers in the same order and do the same
float32 operations per path, so the radiance of every path must be the same bit for bit (not merely
close), at every depth limit and Russian-roulette start, in every Lambertian scene lit by area lights.
The radiance itself is checked against analytic values in test_tracer_analytic.py (the white furnace,
a small area light over a plane), which run through the compiled loop.
"""

from __future__ import annotations

import numpy as np
import pytest

import tracer.integrators as integrators
from tracer import wavefront
from tracer.load import load_scene
from tracer.rendering import render


def _rays(scene, size=(24, 16), spp=3):
    o, d, ok = scene.camera(size=size).rays(samples=spp, seed=5)
    assert ok.all()
    return o.reshape(-1, 3), d.reshape(-1, 3)


def _both(scene, o, d, monkeypatch, **kw):
    out = []
    for fused in (False, True):
        monkeypatch.setattr(integrators, "FUSED", fused)
        out.append(integrators.trace(scene, o, d, np.random.default_rng([3, 1]), **kw))
    return out


@pytest.mark.parametrize("name", ["cornell", "furnace", "arealight"])
@pytest.mark.parametrize("max_depth,rr_depth", [(0, 3), (1, 3), (2, 1), (8, 3), (12, 5)])
def test_compiled_bounces_are_the_numpy_steps_bit_for_bit(name, max_depth, rr_depth, monkeypatch):
    scene = load_scene(name)
    assert wavefront.applies(scene, "path")
    o, d = _rays(scene)
    ref, fused = _both(scene, o, d, monkeypatch, integrator="path", max_depth=max_depth, rr_depth=rr_depth)
    assert ref.dtype == fused.dtype == np.float32
    assert np.all(np.isfinite(ref))
    if max_depth or name == "furnace":  # the box's and the plane's cameras see no emitter directly
        assert ref.max() > 0
    np.testing.assert_array_equal(fused, ref)


def test_rays_that_leave_the_scene_and_rays_that_start_on_the_light(monkeypatch):
    # an open scene: half the rays miss everything; a few start just under the emitter and hit it first
    scene = load_scene("arealight")
    rng = np.random.default_rng(0)
    n = 400
    o = np.zeros((n, 3)) + [0.0, 0.5, 0.0]
    o[:20] = [0.0, 0.99, 0.0]
    d = rng.normal(size=(n, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    ref, fused = _both(scene, o, d, monkeypatch, integrator="path", max_depth=6, rr_depth=2)
    assert (ref == 0).all(axis=1).any() and ref.max() > 1  # misses give zero; the emitter is seen directly
    np.testing.assert_array_equal(fused, ref)


@pytest.mark.parametrize("name,integrator", [("sky", "path"), ("cornell-point", "path"), ("cornell", "direct")])
def test_other_scenes_and_integrators_keep_the_numpy_steps(name, integrator):
    # glossy and mirror materials, environments, point lights and direct lighting are not compiled
    assert not wavefront.applies(load_scene(name), integrator)


def test_image_is_the_same_whatever_the_threads_and_the_rows(monkeypatch):
    monkeypatch.setattr(integrators, "FUSED", True)
    scene = load_scene("cornell")
    cam = scene.camera(size=(40, 24))
    one = render(scene, cam, spp=4, seed=9, threads=1, batch=800)
    two = render(scene, cam, spp=4, seed=9, threads=2, batch=800)
    np.testing.assert_array_equal(one.image, two.image)
    np.testing.assert_array_equal(one.variance, two.variance)
    rows = render(scene, cam, spp=4, seed=9, threads=2, batch=800, rows=(10, 24))
    np.testing.assert_array_equal(rows.image, one.image[10:24])


@pytest.mark.parametrize("name", ["cornell", "sky"])
def test_kernel_ray_casts_are_embreex_answers_bit_for_bit(name):
    # the compiled passes cast rays into their own embree scene: every hit, distance and shadow answer must be
    # the one embreex gives (tracer.accel), for rays from inside and outside the geometry in every direction
    scene = load_scene(name)
    rng = np.random.default_rng(4)
    n = 20000
    lo, hi = (scene.vertices - scene.shift).min(axis=0), (scene.vertices - scene.shift).max(axis=0)
    o = (lo + (hi - lo) * rng.uniform(-0.2, 1.2, size=(n, 3))).astype(np.float32)
    d = rng.normal(size=(n, 3)).astype(np.float32)
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    prim, t = np.empty(n, np.int32), np.empty(n, np.float32)
    wavefront.passes(scene).intersect(o, d, n, prim, t)
    ref_prim, ref_t = scene.accel.intersect(o, d, threads=1)
    assert 0.2 < np.mean(ref_prim >= 0) < 1  # both hits and misses
    np.testing.assert_array_equal(prim, ref_prim)
    np.testing.assert_array_equal(t, ref_t)
    # shadow rays of random reach through the compiled pass: light is added where embreex sees no blocker
    reach = (rng.uniform(0, 1.5, n) * np.linalg.norm(hi - lo)).astype(np.float32)
    blocked = scene.accel.occluded(o, d, reach, threads=1)
    assert 0.05 < blocked.mean() < 0.95
    L = np.zeros((n, 3), np.float32)
    none3, none = np.zeros((0, 3), np.float32), np.zeros(0, np.float32)
    wavefront.passes(scene).settle(0, np.zeros(0, np.int64), none3, none3, none3, L, none, np.zeros(0, bool), n,
                                   np.arange(n), o, d, reach, np.ones((n, 3), np.float32), none3)
    np.testing.assert_array_equal(L[:, 0] == 0, blocked)
