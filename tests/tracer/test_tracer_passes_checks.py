"""The tracer's compiled bounce loop (lenslab.cxx_kernels.LambertScene) refuses a hit on a triangle the scene does
not have: a one-line ValueError, not a read past the scene's triangle arrays."""

from __future__ import annotations

import numpy as np
import pytest

from tracer import wavefront
from tracer.load import load_scene

F32 = np.float32


def _shade(prim: int):
    scene = load_scene("cornell")
    assert wavefront.applies(scene, "path")  # CI builds the passes and has embree (pyproject's test extra)
    lam = wavefront.passes(scene)
    z3 = lambda: np.zeros((1, 3), F32)  # noqa: E731
    d = np.array([[0.0, 0.0, -1.0]], F32)
    return lam.shade(np.array([prim], np.int32), np.ones(1, F32), z3(), d, np.ones((1, 3), F32), z3(),
                     np.ones(1, F32), np.zeros(1, bool), np.zeros(1, np.int64), z3(), np.full((1, 4), 0.5, F32),
                     np.full((1, 3), 0.5, F32), np.ones(1, F32), np.zeros(1, F32), np.full(1, 0.5, F32), 1.0, 1e-4,
                     1e-4, False, False, np.zeros(1, bool), np.zeros(1, np.int64), z3(), z3(), np.zeros(1, F32), z3())


@pytest.mark.parametrize("beyond", [0, 1, 2 ** 31 - 1 - 10 ** 6])
def test_a_hit_on_a_triangle_beyond_the_scene_is_refused(beyond):
    ntri = len(load_scene("cornell").material_ids)
    with pytest.raises(ValueError, match="triangle"):
        _shade(ntri + beyond)


def test_a_hit_on_the_last_triangle_is_shaded():
    """The same call on the scene's last triangle shades the one path (the arguments above are well formed)."""
    m, g = _shade(len(load_scene("cornell").material_ids) - 1)
    assert (m, g) in {(0, 0), (1, 0), (0, 1), (1, 1)}
