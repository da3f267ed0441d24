"""The compiled light sampling (tracer.kernels) against the NumPy steps it replaces: the same image bit for
bit, for every built-in scene with area lights and both integrators. The light transport itself is checked
against analytic values in test_tracer_analytic.py (furnace, area light over a plane), which run through
the compiled pass."""

from __future__ import annotations

import numpy as np
import pytest

import tracer.integrators as integrators
from tracer.load import load_scene
from tracer.rendering import render


@pytest.mark.parametrize("name", ["cornell", "arealight"])
@pytest.mark.parametrize("integrator", ["path", "direct"])
def test_fused_light_sampling_is_the_numpy_one(name, integrator, monkeypatch):
    scene = load_scene(name)
    camera = scene.camera(size=(48, 32))
    images = []
    for fused in (False, True):
        monkeypatch.setattr(integrators, "FUSED", fused)
        images.append(render(scene, camera, spp=4, seed=7, integrator=integrator, threads=2).image)
    assert scene.has_area_lights
    np.testing.assert_array_equal(images[1], images[0])  # the same float32 operations in the same order
