"""The bilinear samplers (compiled, and their NumPy reference) keep finite input finite at every magnitude
float32 holds: taps from 0 to 1e30 and up to the largest float32, of either sign, side by side. Expected
values: the bilinear formula ``sum w_k v_k`` with ``w = (1-tx)(1-ty), tx(1-ty), (1-tx)ty, tx ty`` in float64
here. Bound: the float32 lerps of the kernel are within 4 ulp of the largest tap of the exact value (see
tests/warp/test_native_kernels.py); where they would overflow the float64 sum is used, within 1 ulp."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from lenslab import cxx_kernels as K
from lenslab.lenses import Camera
from lenslab.warp import WarpPlan, warp
from lenslab.warp.kernels import reference as ref
from lenslab.warp.seam import Border

BIG = float(np.finfo(np.float32).max)
EPS32 = float(np.finfo(np.float32).eps)
FLAT = Border()


def bilinear64(src, x, y):
    """The bilinear value at index coordinates (x, y) inside the image, in float64 (no border handling)."""
    s = src.astype(np.float64)
    i, j = np.floor(x).astype(int), np.floor(y).astype(int)
    tx, ty = (x - i)[:, None], (y - j)[:, None]
    return ((1 - tx) * (1 - ty) * s[j, i] + tx * (1 - ty) * s[j, i + 1] + (1 - tx) * ty * s[j + 1, i]
            + tx * ty * s[j + 1, i + 1])


def checker(h, w, nc, magnitude):
    """+m and -m in a checkerboard: every 2 x 2 neighbourhood holds both signs."""
    sign = np.where((np.arange(h)[:, None] + np.arange(w)[None, :]) % 2 == 0, 1.0, -1.0)
    return np.repeat((sign * magnitude)[..., None], nc, axis=2).astype(np.float32)


def positions(n, w, h, seed):
    rng = np.random.default_rng(seed)
    x = rng.uniform(0, w - 1.0001, n).astype(np.float32)
    y = rng.uniform(0, h - 1.0001, n).astype(np.float32)
    x[:8], y[:8] = np.float32(2.0), np.float32(1.0)  # pixel centres: weights exactly 1 and 0
    return x, y


def deviation(out, want, src):
    """(largest |out - want|, the bound 4 ulp of the largest tap) for a sampler's ``out`` against ``want``."""
    return float(np.abs(out.astype(np.float64) - want).max()), 4 * EPS32 * float(np.abs(src).max())


def check(out, want, src):
    assert np.isfinite(out).all()
    err, bound = deviation(out, want, src)
    assert err <= bound


@pytest.mark.parametrize("magnitude", [1e30, 1.7e38, 2.5e38, BIG])
@pytest.mark.parametrize("nc", [1, 3, 4, 5])
def test_single_tap_sampler_opposite_signs(magnitude, nc):
    src = checker(6, 7, nc, magnitude)
    x, y = positions(2000, 7, 6, seed=nc)
    out, alpha = np.empty((2000, nc), np.float32), np.empty(2000, np.float32)
    K.bilinear1(src.reshape(-1), 7, 6, nc, x, y, np.ones(2000, bool), *FLAT.flags, out, alpha)
    want = bilinear64(src, x.astype(np.float64), y.astype(np.float64))
    mine, _ = ref.bilinear1(src, x, y, np.ones(2000, bool), FLAT.flags)
    for got in (out, mine):  # the compiled sampler and its NumPy reference
        err, bound = deviation(got, want, src)
        assert np.isfinite(got).all() and err <= bound


@pytest.mark.parametrize("magnitude", [1e30, 2.5e38, BIG])
def test_cached_taps_and_the_folding_sampler(magnitude):
    src = checker(6, 7, 3, magnitude)
    rng = np.random.default_rng(9)
    x = rng.uniform(-1.5, 7.5, 3000).astype(np.float32)  # beyond the edges too: folded taps
    y = rng.uniform(-1.5, 6.5, 3000).astype(np.float32)
    v = np.ones(3000, bool)
    off, tx, ty = np.empty(3000, np.uint32), np.empty(3000, np.float32), np.empty(3000, np.float32)
    K.taps_of(7, 6, x, y, v, off, tx, ty)
    out, alpha = np.empty((3000, 3), np.float32), np.empty(3000, np.float32)
    K.from_taps(src.reshape(-1), 7, 3, off, tx, ty, out, alpha)
    fold = np.flatnonzero(off == ref.FOLDED)
    assert len(fold) > 100
    K.folded(src.reshape(-1), 7, 6, 3, fold, x[fold], y[fold], *FLAT.flags, out, alpha)
    assert np.isfinite(out).all()
    want, _ = ref.bilinear1(src, x, y, v, FLAT.flags)
    np.testing.assert_allclose(out, want, rtol=0, atol=4 * EPS32 * magnitude)
    inside = (x >= 0) & (x < 6) & (y >= 0) & (y < 5)
    check(out[inside], bilinear64(src, x[inside].astype(np.float64), y[inside].astype(np.float64)), src)


@pytest.mark.parametrize("ns", [2, 4, 16])
def test_supersampled_sampler_opposite_signs(ns):
    src = checker(6, 7, 3, BIG)
    x, y = positions(300 * ns, 7, 6, seed=ns)
    out, alpha = np.empty((300, 3), np.float32), np.empty(300, np.float32)
    K.bilinear_n(src.reshape(-1), 7, 6, 3, x.reshape(300, ns), y.reshape(300, ns), np.ones((300, ns), bool),
                 *FLAT.flags, out, alpha)
    want = bilinear64(src, x.astype(np.float64), y.astype(np.float64)).reshape(300, ns, 3).mean(axis=1)
    mine, _ = ref.bilinear_n(src, x.reshape(300, ns), y.reshape(300, ns), np.ones((300, ns), bool), FLAT.flags)
    for got in (out, mine):  # the compiled sampler and its NumPy reference
        err, bound = deviation(got, want, src)
        assert np.isfinite(got).all() and err <= bound


@settings(max_examples=200, deadline=None)
@given(exponents=st.lists(st.floats(-3.0, 38.53), min_size=4, max_size=4),
       signs=st.lists(st.sampled_from([-1.0, 1.0]), min_size=4, max_size=4),
       tx=st.floats(0.0, 1.0, exclude_max=True, width=32), ty=st.floats(0.0, 1.0, exclude_max=True, width=32))
def test_any_finite_taps_give_a_finite_value_between_them(exponents, signs, tx, ty):
    taps = np.array([s * min(10.0 ** e, BIG) for s, e in zip(signs, exponents)], np.float32)
    src = taps.reshape(2, 2, 1)
    x, y = np.array([tx], np.float32), np.array([ty], np.float32)
    out, alpha = np.empty((1, 1), np.float32), np.empty(1, np.float32)
    K.bilinear1(src.reshape(-1), 2, 2, 1, x, y, np.ones(1, bool), *FLAT.flags, out, alpha)
    want = bilinear64(src, x.astype(np.float64), y.astype(np.float64))
    check(out, want, src)
    assert taps.min() <= out[0, 0] <= taps.max()


def test_the_warp_of_a_finite_source_near_the_largest_float32_stays_finite():
    src = np.repeat(checker(16, 32, 1, BIG), 3, axis=2)
    cams = Camera.from_spec("equirect", (32, 16)), Camera.from_spec("equirect", (64, 32))
    for how in ({}, {"samples": 4}, {"cache": True}):
        plan = WarpPlan(*cams, **how)
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # no note of non-finite values: there are none
            out, alpha = plan.run(src)
            if how.get("cache"):
                out, alpha = plan.run(src)  # the kept taps
        assert np.isfinite(out).all() and np.abs(out).max() <= BIG
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        cube = np.repeat(checker(32, 48, 1, BIG), 3, axis=2)  # a source of pieces: taps read across faces
        out, _ = warp(cube, Camera.from_spec("cubemap", (48, 32)), Camera.from_spec("perspective:fov=90", (24, 24)))
    assert np.isfinite(out).all()
