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
