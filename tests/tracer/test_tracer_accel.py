"""The embree accelerator against a brute-force NumPy Moller-Trumbore intersector."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from tracer.accel import Accelerator


def brute_force(v, tris, o, d):
    """Closest hit of every ray against every triangle (float64 Moller-Trumbore, two-sided).

    Returns triangle index (-1 for a miss), distance, and a margin: how far inside its triangle the
    hit lies (smallest barycentric) and the gap to the next-closest hit, to tell ambiguous cases.
    """
    p0, p1, p2 = v[tris[:, 0]], v[tris[:, 1]], v[tris[:, 2]]
    e1, e2 = p1 - p0, p2 - p0
    pv = np.cross(d[:, None, :], e2[None])
    det = np.einsum("tk,rtk->rt", e1, pv)
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / det
        tv = o[:, None, :] - p0[None]
        u = np.einsum("rtk,rtk->rt", tv, pv) * inv
        qv = np.cross(tv, e1[None])
        w = np.einsum("rk,rtk->rt", d, qv) * inv
        t = np.einsum("tk,rtk->rt", e2, qv) * inv
    ok = (np.abs(det) > 1e-12) & (u >= 0) & (w >= 0) & (u + w <= 1) & (t > 0)
    t = np.where(ok, t, np.inf)
    order = np.argsort(t, axis=1)
    best = order[:, 0]
    rows = np.arange(len(o))
    dist = t[rows, best]
    second = t[rows, order[:, 1]]
    bary = np.minimum.reduce([u[rows, best], w[rows, best], 1 - u[rows, best] - w[rows, best]])
    prim = np.where(np.isfinite(dist), best, -1)
    with np.errstate(invalid="ignore"):  # inf - inf for rays that miss everything
        gap = np.where(np.isfinite(dist), second - dist, np.inf)
    return prim, dist, bary, gap


def random_soup(rng, n_tris=150):
    centres = rng.uniform(-1, 1, (n_tris, 3))
    v = (centres[:, None, :] + rng.normal(scale=0.25, size=(n_tris, 3, 3))).reshape(-1, 3)
    return v, np.arange(3 * n_tris).reshape(-1, 3)


@settings(max_examples=8, deadline=None)
@given(st.integers(0, 2**31 - 1))
def test_embree_matches_brute_force_on_random_rays(seed):
    rng = np.random.default_rng(seed)
    v, tris = random_soup(rng)
    acc = Accelerator(v, tris)
    o = rng.uniform(-2, 2, (1500, 3))
    d = rng.normal(size=(1500, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    prim, dist = acc.intersect(o, d, threads=2)
    ref, ref_dist, bary, gap = brute_force(v, tris, o, d)
    # embree works in float32: leave out rays that graze a triangle edge (barycentric margin below
    # 1e-4) or whose two nearest hits are within 1e-4; every other ray must agree exactly
    clear = ((ref < 0) | ((bary > 1e-4) & (gap > 1e-4)))
    assert clear.mean() > 0.95
    np.testing.assert_array_equal(prim[clear], ref[clear])
    hit = clear & (ref >= 0)
    assert hit.sum() > 100
    np.testing.assert_allclose(dist[hit], ref_dist[hit], atol=1e-4)  # float32 distances of order 1
    assert np.all(np.isinf(dist[prim < 0]))


def test_occlusion_respects_the_distance_limit():
    rng = np.random.default_rng(1)
    v, tris = random_soup(rng)
    acc = Accelerator(v, tris)
    o = rng.uniform(-2, 2, (2000, 3))
    d = rng.normal(size=(2000, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    ref, ref_dist, bary, gap = brute_force(v, tris, o, d)
    tmax = rng.uniform(0, 4, 2000)
    clear = (np.abs(ref_dist - tmax) > 1e-3) & ((ref < 0) | (bary > 1e-4))
    blocked = acc.occluded(o, d, tmax, threads=1)
    np.testing.assert_array_equal(blocked[clear], (ref_dist < tmax)[clear])
    # no limit: occluded exactly where there is a hit
    np.testing.assert_array_equal(acc.occluded(o, d)[clear], (ref >= 0)[clear])


def test_threaded_and_single_thread_queries_agree():
    rng = np.random.default_rng(2)
    v, tris = random_soup(rng, 400)
    acc = Accelerator(v, tris)
    o = rng.uniform(-2, 2, (60_000, 3))
    d = rng.normal(size=(60_000, 3))
    p1, t1 = acc.intersect(o, d, threads=1)
    p2, t2 = acc.intersect(o, d, threads=4)
    np.testing.assert_array_equal(p1, p2)
    np.testing.assert_array_equal(t1, t2)


def test_far_from_origin_scene_keeps_precision():
    """Vertices far from the world origin are shifted before float32 conversion."""
    rng = np.random.default_rng(3)
    v, tris = random_soup(rng)
    offset = np.array([1e4, -2e4, 5e3])
    acc = Accelerator(v + offset, tris)
    o = rng.uniform(-2, 2, (1000, 3))
    d = rng.normal(size=(1000, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    prim, dist = acc.intersect(o + offset, d)
    ref, ref_dist, bary, gap = brute_force(v, tris, o, d)
    clear = ((ref < 0) | ((bary > 1e-4) & (gap > 1e-4)))
    np.testing.assert_array_equal(prim[clear], ref[clear])
    hit = clear & (ref >= 0)
    # origins 2e4 from zero in float64, shifted to the scene centre: distances as good as near zero
    np.testing.assert_allclose(dist[hit], ref_dist[hit], atol=1e-4)
