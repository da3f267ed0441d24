"""The compiled bounce loop casts rays in packets (embree's rtcIntersect<K>/rtcOccluded<K>, K =
``lenslab.cxx_kernels.LAMBERT_PACKET``); embreex casts one ray at a time (rtcIntersect1). The image is the NumPy
steps' bit for bit only if every packet answer is embreex's: checked here on the rays that matter most, those
that leave a surface just above it (every bounce and every shadow ray) and those aimed at the triangles' shared
edges and corners, where a hit could fall to either neighbour; and an answer must not depend on the other rays
of its packet (the bands of a render differ in their live paths).
"""

from __future__ import annotations

import numpy as np
import pytest

from tracer import wavefront
from tracer.load import load_scene

pytestmark = pytest.mark.skipif(not wavefront.native(), reason="the compiled passes are built by pip install -e .")


def _unit(v):
    return (v / np.linalg.norm(v, axis=1, keepdims=True)).astype(np.float32)


def _surface_rays(scene, rng, n):
    """Rays from uniform points on random triangles, ``scene.epsilon`` above them (as the loop offsets a
    bounce), into the hemisphere of the side they start on."""
    k = rng.integers(0, len(scene.triangles), n)
    u = rng.uniform(size=(n, 2))
    su = np.sqrt(u[:, 0])
    b1, b2 = 1 - su, u[:, 1] * su
    p = scene.v0[k] + b1[:, None] * scene.e1[k] + b2[:, None] * scene.e2[k]
    side = np.where(rng.uniform(size=n) < 0.5, 1.0, -1.0)[:, None]
    nrm = scene.normals[k] * side
    o = (p + scene.epsilon * nrm).astype(np.float32)
    d = _unit(rng.normal(size=(n, 3)))
    d = np.where(((d * nrm).sum(axis=1) < 0)[:, None], -d, d).astype(np.float32)
    return o, d


def _edge_rays(scene, rng, n):
    """Rays from random points in the scene's box to points on the triangles' edges and at their corners."""
    lo, hi = scene.v0.min(axis=0), scene.v0.max(axis=0)
    k = rng.integers(0, len(scene.triangles), n)
    t = np.where(rng.uniform(size=n) < 0.25, 0.0, rng.uniform(size=n))[:, None]  # a quarter at a corner
    edge = rng.integers(0, 3, n)
    v1, v2 = scene.v0[k] + scene.e1[k], scene.v0[k] + scene.e2[k]
    a = np.choose(edge[:, None], [scene.v0[k], v1, v2])
    b = np.choose(edge[:, None], [v1, v2, scene.v0[k]])
    target = a + t * (b - a)
    o = (lo + (hi - lo) * rng.uniform(0.05, 0.95, size=(n, 3))).astype(np.float32)
    return o, _unit(target - o)


@pytest.mark.parametrize("name", ["cornell", "arealight", "furnace"])
def test_packet_casts_are_embreex_answers_at_surfaces_edges_and_corners(name):
    scene = load_scene(name)
    rng = np.random.default_rng(11)
    passes = wavefront.passes(scene)
    for o, d in (_surface_rays(scene, rng, 30000), _edge_rays(scene, rng, 30000)):
        n = len(o)
        prim, t = np.empty(n, np.int32), np.empty(n, np.float32)
        passes.intersect(o, d, n, prim, t)
        ref_prim, ref_t = scene.accel.intersect(o, d, threads=1)
        assert np.mean(ref_prim >= 0) > 0.2  # the rays meet geometry (the plane scene is open: a quarter do)
        np.testing.assert_array_equal(prim, ref_prim)
        np.testing.assert_array_equal(t, ref_t)
        # shadow rays to just short of the hit (visible) and beyond it (blocked where something is hit)
        reach = np.where(rng.uniform(size=n) < 0.5, 0.5, 1.5).astype(np.float32) * np.minimum(ref_t, 1e3)
        blocked = scene.accel.occluded(o, d, reach, threads=1)
        assert 0.05 < blocked.mean() < 0.95
        L = np.zeros((n, 3), np.float32)
        none3, none = np.zeros((0, 3), np.float32), np.zeros(0, np.float32)
        passes.settle(0, np.zeros(0, np.int64), none3, none3, none3, L, none, np.zeros(0, bool), n, np.arange(n), o,
                      d, reach, np.ones((n, 3), np.float32), none3)
        np.testing.assert_array_equal(L[:, 0] == 0, blocked)


def test_a_ray_answer_does_not_depend_on_its_packet():
    scene = load_scene("cornell")
    rng = np.random.default_rng(12)
    o, d = _surface_rays(scene, rng, 4099)  # not a whole number of packets: the last one is partly empty
    passes = wavefront.passes(scene)
    n = len(o)
    prim, t = np.empty(n, np.int32), np.empty(n, np.float32)
    passes.intersect(o, d, n, prim, t)
    order = rng.permutation(n)
    prim2, t2 = np.empty(n, np.int32), np.empty(n, np.float32)
    passes.intersect(np.ascontiguousarray(o[order]), np.ascontiguousarray(d[order]), n, prim2, t2)
    np.testing.assert_array_equal(prim2, prim[order])
    np.testing.assert_array_equal(t2, t[order])
