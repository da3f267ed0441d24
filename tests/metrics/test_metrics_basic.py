"""Error metrics: exact values on constructed images, masking, noise floor, edges."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lenslab import metrics


def _img(h=32, w=48, seed=0):
    rng = np.random.default_rng(seed)
    return (0.1 + rng.random((h, w, 3))).astype(np.float32)


def test_relative_l1_exact_and_masked():
    r = _img()
    t = r * np.float32(1.01)
    # every value off by exactly 1%: sum|t-r| / sum|r| = 0.01 (float32 rounding of r*1.01: ~1e-7 relative)
    assert metrics.relative_l1(r, t) == pytest.approx(0.01, rel=1e-5)
    t2 = t.copy()
    t2[:4] = 1e6  # masked-out rows cannot change the result
    mask = np.ones(r.shape[:2], bool)
    mask[:4] = False
    assert metrics.relative_l1(r, t2, mask) == pytest.approx(0.01, rel=1e-5)
    assert math.isnan(metrics.relative_l1(r, t, np.zeros(r.shape[:2], bool)))
    z = np.zeros_like(r)
    assert metrics.relative_l1(z, z) == 0.0
    assert metrics.relative_l1(z, r) == math.inf


def test_valid_mask_from_alphas():
    a = np.ones((4, 5), np.float32)
    b = a.copy()
    a[0, 0] = 0.5   # partial coverage in the reference
    b[1, 1] = 0.0   # nothing in the test
    b[2, 2] = np.nan
    m = metrics.valid_mask(a, b)
    assert m.sum() == 20 - 3 and not m[0, 0] and not m[1, 1] and not m[2, 2]
    assert metrics.valid_mask(shape=(2, 3)).all()


def test_psnr_log_of_a_constant_factor():
    r = _img(seed=1).astype(np.float64)
    k = 1.05
    t = r * k
    eps = 1e-3 * r.mean()
    lr = np.log(r + eps)
    lt = np.log(t + eps)
    expected = 10 * math.log10((lr.max() - lr.min()) ** 2 / np.mean((lt - lr) ** 2))
    assert metrics.psnr_log(r, t) == pytest.approx(expected, rel=1e-9)
    assert metrics.psnr_log(r, r) == math.inf


def test_share_off_counts_pixels():
    r = np.ones((10, 10, 3), np.float32)
    t = r.copy()
    t[:2, :5] *= 1.10    # 10 pixels 10% off
    t[5, :3] *= 1.049    # 3 pixels just under 5%: not counted
    assert metrics.share_off(r, t) == pytest.approx(0.10)
    assert metrics.share_off(r, t, tolerance=0.04) == pytest.approx(0.13)


def test_flip_zero_for_identical_and_grows_with_error():
    r = _img(64, 64, 3)
    assert metrics.flip(r, r) == pytest.approx(0.0, abs=1e-6)
    small = metrics.flip(r, r * 1.02)
    large = metrics.flip(r, r * 1.5)
    assert 0 < small < large <= 1
    # a large error confined to masked-out pixels: the masked mean counts only the rest, which FLIP
    # still sees as nearly identical (its filters reach a few pixels, so a small leak is allowed)
    t = r.copy()
    t[:, :16] = 50.0
    mask = np.ones((64, 64), bool)
    mask[:, :24] = False
    assert metrics.flip(r, t, mask) < 0.05 * metrics.flip(r, t)


def test_noise_floor_matches_simulated_noise():
    rng = np.random.default_rng(7)
    truth = np.full((200, 200, 3), 2.0)
    sigma = 0.1
    noisy = truth + rng.normal(0.0, sigma, truth.shape)
    stderr = np.full(truth.shape, sigma)
    nf = metrics.noise_floor(noisy, stderr)
    measured = metrics.relative_l1(noisy, truth)
    # expected relative L1 sqrt(2/pi) * 0.1 / 2 = 3.99%; with 120000 samples the measured mean |noise|
    # has a relative standard error of sqrt(pi/2 - 1)/sqrt(120000) = 0.2%: allow 1%
    assert measured == pytest.approx(math.sqrt(2 / math.pi) * sigma / 2.0, rel=0.01)
    assert nf["l1"] == pytest.approx(measured, rel=0.01)
    assert nf["rmse"] == pytest.approx(sigma)
    # compare() reports the floor and what exceeds it: a pure-noise reference leaves almost no excess
    c = metrics.compare(noisy, truth, ref_stderr=stderr, with_flip=False)
    assert c["noise_l1"] == pytest.approx(nf["l1"])
    assert c["excess_l1"] < 0.01 * c["l1"]


def test_edges_from_aovs_reach_exactly_radius():
    pid = np.zeros((20, 30), int)
    pid[:, 15:] = 1  # a vertical boundary between columns 14 and 15
    e = metrics.edge_mask_from_aovs(prim_id=pid, radius=2)
    cols = np.nonzero(e[10])[0]
    assert cols.tolist() == [12, 13, 14, 15, 16, 17]  # the two boundary pixels and 2 px either side
    depth = np.where(np.arange(30)[None, :] < 10, 1.0, 5.0) * np.ones((20, 1))
    e2 = metrics.edge_mask_from_aovs(depth=depth, radius=1)
    assert np.nonzero(e2[3])[0].tolist() == [8, 9, 10, 11]
    normal = np.zeros((20, 30, 3))
    normal[..., 2] = 1.0
    normal[12:, :, :] = (0.0, 1.0, 0.0)
    e3 = metrics.edge_mask_from_aovs(normal=normal, radius=0)
    assert np.nonzero(e3[:, 5])[0].tolist() == [11, 12]
    with pytest.raises(ValueError):
        metrics.edge_mask_from_aovs()


def test_edges_from_noisy_image_find_the_step_not_the_noise():
    rng = np.random.default_rng(3)
    img = np.ones((40, 60, 3))
    img[:, 30:] = 4.0  # a shadow edge: a 4x step
    img *= 1.0 + 0.05 * rng.standard_normal(img.shape)  # 5% Monte Carlo-like noise
    e = metrics.edge_mask_from_image(img, radius=2)
    assert e[:, 27:33].all()  # the step and 2 px around it
    assert not e[:, :25].any() and not e[:, 35:].any()  # the noise alone is not an edge


def test_compare_splits_edges_and_interior():
    r = _img(32, 32, 5)
    t = r.copy()
    edges = np.zeros((32, 32), bool)
    edges[:, :8] = True
    t[:, :8] *= 1.2  # all error on the edges
    c = metrics.compare(r, t, edges=edges, with_flip=True)
    assert c["pixels_edge"] + c["pixels_interior"] == c["pixels"] == 32 * 32
    assert c["l1_interior"] == 0.0
    assert c["l1_edge"] == pytest.approx(0.2, rel=1e-5)
    assert c["flip_edge"] > c["flip_interior"]


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 10_000), st.floats(0.01, 100.0))
def test_relative_l1_scale_invariant_and_nonnegative(seed, scale):
    rng = np.random.default_rng(seed)
    r = rng.random((8, 9, 3)) + 0.01
    t = r + rng.normal(0, 0.1, r.shape)
    e = metrics.relative_l1(r, t)
    assert e >= 0
    # relative L1 does not depend on the units of radiance
    assert metrics.relative_l1(r * scale, t * scale) == pytest.approx(e, rel=1e-9)
    # the triangle inequality through a third image
    u = r + rng.normal(0, 0.1, r.shape)
    assert e <= metrics.relative_l1(r, u) + np.abs(t - u).sum() / np.abs(r).sum() + 1e-12
