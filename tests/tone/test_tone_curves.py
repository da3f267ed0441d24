"""Each tone curve against its published formula, evaluated independently here in float64, and the
properties every curve must have: monotonic over 0..1e30, exactly 0 at 0, never above 1, defined at
denormals."""

from __future__ import annotations

import math

import colour
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lenslab import tone

# float32 evaluation of a rational curve of a few operations against a float64 reference: each
# operation rounds by at most 2^-24 relative, a dozen of them stay well inside 1e-5
RTOL = 1e-5
ATOL = 1e-7  # near 0 the absolute float32 rounding of values ~1e-3 is ~1e-10; 1e-7 is generous but tight

POINTS = np.array([0.0, 1e-6, 1e-3, 0.01, 0.05, 0.18, 0.5, 1.0, 2.0, 4.0, 5.6, 8.0, 11.2, 100.0, 1e4])
GLOBAL = [n for n, c in tone.CURVES.items() if c.kind != "local"]


def u2(x):
    """Uncharted 2 partial curve exactly as published (Hable 2010), float64."""
    A, B, C, D, E, F = 0.15, 0.50, 0.10, 0.20, 0.02, 0.30
    return ((x * (A * x + C * B) + D * E) / (x * (A * x + B) + D * F)) - E / F


def u2_gdc(x):
    A, B, C, D, E, F = 0.22, 0.30, 0.10, 0.20, 0.01, 0.30
    return ((x * (A * x + C * B) + D * E) / (x * (A * x + B) + D * F)) - E / F


def test_hable_matches_the_seed_reference_values():
    # the seed: exposure bias 2.0, white 11.2, no clamp; hable(1.0) = U2(2) / U2(11.2)
    ref = u2(2.0 * POINTS) / u2(11.2)
    assert u2(2.0) / u2(11.2) == pytest.approx(0.4929185, abs=5e-7)  # the published constants' value
    got = tone.hable(POINTS.astype(np.float32))
    np.testing.assert_allclose(got, np.minimum(ref, 1.0), rtol=RTOL, atol=ATOL)
    assert tone.hable(np.float32([5.6]))[0] == 1.0  # 5.6 * bias 2.0 = white 11.2
    assert tone.hable(np.float32([0.0]))[0] == 0.0


def test_hable_gdc_preset_and_custom_constants():
    ref = np.minimum(u2_gdc(2.0 * POINTS) / u2_gdc(11.2), 1.0)
    np.testing.assert_allclose(tone.hable(POINTS.astype(np.float32), preset="gdc"), ref, rtol=RTOL, atol=ATOL)
    # every constant is a parameter: giving the GDC set by hand is the same curve
    custom = tone.hable(POINTS.astype(np.float32), A=0.22, B=0.30, E=0.01)
    np.testing.assert_allclose(custom, ref, rtol=RTOL, atol=ATOL)
    # bias and white move the curve as the formula says
    ref2 = np.minimum(u2(3.0 * POINTS) / u2(6.0), 1.0)
    np.testing.assert_allclose(tone.hable(POINTS.astype(np.float32), exposure_bias=3.0, white=6.0), ref2,
                               rtol=RTOL, atol=ATOL)


def test_exposure_is_a_multiplier_in_stops():
    for ev in (-3.0, 1.5, 4.0):
        got = tone.tonemap(POINTS.astype(np.float32), "hable", exposure=ev)
        ref = np.minimum(u2(2.0 * POINTS * 2.0 ** ev) / u2(11.2), 1.0)
        np.testing.assert_allclose(got, ref, rtol=RTOL, atol=ATOL)


def test_reinhard_extended_white_point_reaches_one():
    got = tone.reinhard_extended(np.float32([2.5, 5.0, 6.0]), white=5.0)
    assert got[1] == 1.0 and got[2] == 1.0
    assert got[0] == pytest.approx(2.5 * (1 + 2.5 / 25) / 3.5, rel=RTOL)


def test_reinhard2002_key_and_log_average():
    x = np.float32([0.0, 0.01, 0.1, 1.0, 10.0])
    got = tone.reinhard2002(x, key=0.18, log_avg=0.5)
    L = 0.18 / 0.5 * x.astype(np.float64)
    np.testing.assert_allclose(got, L / (1 + L), rtol=RTOL, atol=ATOL)
    # without log_avg: Reinhard's exp(mean(log(delta + Lw))) over the values themselves
    lavg = math.exp(np.mean(np.log(1e-4 + x.astype(np.float64))))
    L = 0.18 / lavg * x.astype(np.float64)
    np.testing.assert_allclose(tone.reinhard2002(x), L / (1 + L), rtol=RTOL, atol=ATOL)
    # burn-out white in scaled units: eq. 4
    got = tone.reinhard2002(x, key=0.18, log_avg=0.18, white=2.0)
    L = x.astype(np.float64)
    np.testing.assert_allclose(got, np.minimum(L * (1 + L / 4) / (1 + L), 1), rtol=RTOL, atol=ATOL)


def test_reinhard2002_in_tonemap_is_exposure_invariant():
    rng = np.random.default_rng(3)
    img = (0.3 * np.exp2(rng.normal(0, 2, (16, 16, 3)))).astype(np.float32)
    a = tone.tonemap(img, "reinhard2002", exposure=0)
    b = tone.tonemap(img, "reinhard2002", exposure=3)
    # the key scaling cancels the exposure except through delta = 1e-4, far below these pixels
    np.testing.assert_allclose(a, b, rtol=1e-3, atol=1e-5)


SWEEP = np.unique(np.concatenate([[0.0, 1e-45, 1e-40, 1.17e-38], np.logspace(-38, 30, 6000)]).astype(np.float32))


@pytest.mark.parametrize("name", GLOBAL)
def test_monotonic_bounded_zero_at_zero_and_defined_at_denormals(name):
    y = tone.tonemap(SWEEP, name)
    assert y.dtype == np.float32 and np.all(np.isfinite(y))
    assert y[0] == 0.0, "a curve must map 0 to exactly 0"
    assert np.all(y >= 0) and np.all(y <= 1)
    assert np.all(np.diff(y) >= 0), f"{name} decreases at {SWEEP[1:][np.diff(y) < 0][:5]}"
    # RGB curves on grey pixels, per channel mode: same properties
    grey = tone.tonemap(np.repeat(SWEEP[:, None], 3, axis=1)[None], name)[0]
    assert np.all(np.isfinite(grey)) and np.all(grey >= 0) and np.all(grey <= 1)
    assert np.all(grey[0] == 0)
    lum = grey @ tone.luminance_weights()
    assert np.all(np.diff(lum) >= -1e-6)  # 1e-6: float32 rounding of the weighted sum of 3 channels


@settings(max_examples=300, deadline=None)
@given(a=st.floats(0, float(np.float32(1e30)), width=32), b=st.floats(0, float(np.float32(1e30)), width=32),
       name=st.sampled_from(GLOBAL), ev=st.sampled_from([-8.0, 0.0, 3.5]))
def test_monotonic_property(a, b, name, ev):
    lo, hi = sorted((a, b))
    y = tone.tonemap(np.float32([lo, hi]), name, exposure=ev)
    assert 0 <= y[0] <= y[1] <= 1


@settings(max_examples=200, deadline=None)
@given(rgb=st.lists(st.floats(0, 1e6, width=32), min_size=3, max_size=3), name=st.sampled_from(GLOBAL),
       mode=st.sampled_from(["per-channel", "luminance"]))
def test_rgb_outputs_stay_in_range(rgb, name, mode):
    y = tone.tonemap(np.float32(rgb).reshape(1, 1, 3), name, mode=mode)
    assert np.all(np.isfinite(y)) and np.all(y >= 0) and np.all(y <= 1)


def test_curve_functions_are_pure_and_keep_shape_and_dtype():
    x = np.linspace(0, 20, 24, dtype=np.float64).reshape(2, 3, 4)
    before = x.copy()
    for fn in (tone.clamp, tone.reinhard, tone.hable, tone.aces):
        y = fn(x)
        assert y.shape == x.shape and y.dtype == np.float32
        np.testing.assert_array_equal(x, before)


def test_every_curve_has_a_docstring_with_formula_and_declared_params():
    for name, curve in tone.CURVES.items():
        assert len(curve.doc) > 60, name
        for p in curve.params:
            assert p.doc and p.describe_range()
    assert {"clamp", "gamma", "reinhard", "reinhard-extended", "reinhard2002", "hable", "aces", "aces-hill",
            "agx", "pbr-neutral", "drago", "mantiuk"} <= set(tone.CURVES)


@pytest.mark.parametrize("name", GLOBAL)
def test_monotonic_between_neighbouring_floats(name):
    # 2 x 20000 consecutive float32 values around each point: no rounding step may reverse the order
    for centre in (1e-4, 0.003, 0.08, 0.18, 0.76, 1.0, 5.59, 7.2, 30.0):
        base = np.float32(centre).view(np.int32)
        xs = (base + np.arange(-20000, 20000, dtype=np.int32)).view(np.float32)
        y = tone.tonemap(xs, name)
        assert np.all(np.diff(y) >= 0), f"{name} steps back near {centre}"


@pytest.mark.parametrize("g", [0.5, 1.0, 1.8, 2.2, 2.4, 4.0])
def test_gamma_is_the_srgb_eotf_of_the_power_for_any_gamma(g):
    x = np.concatenate([POINTS, np.float32(0.04045) ** g * np.float32([0.999, 1.0, 1.001])]).astype(np.float32)
    v = np.minimum(x.astype(np.float64), 1.0) ** (1 / g)
    ref = colour.models.eotf_sRGB(v)
    got = tone.gamma(x, gamma=g)
    # four float32 log2/exp2 steps of a few ulps each; 3e-7 more where the sRGB segments meet
    np.testing.assert_allclose(got, ref, rtol=RTOL, atol=ATOL)
    assert got[0] == 0.0
    assert np.all(got[x >= 1] == 1.0)  # white is exactly white, for the writer's sRGB encoding
    # written through the sRGB encoding, the code value is the plain power: what pow(c, 1/g) gives
    np.testing.assert_allclose(colour.models.eotf_inverse_sRGB(got.astype(np.float64)), v, atol=2e-6)


@pytest.mark.parametrize("g", [0.7, 2.2, 3.0])
def test_gamma_steps_never_back_across_its_knee_and_floor(g):
    # consecutive float32 inputs around the input where v reaches the sRGB knee 0.04045, and
    # around the smallest input whose logarithm is taken (below it the output is exactly 0)
    knee = np.float32(0.04045 ** g)
    floor = np.float32(max(2.0 ** -149, 2.0 ** (-126.0 * g)))
    for centre in (knee, floor, np.float32(1.0)):
        base = np.int64(centre.view(np.int32))
        xs = np.clip(base + np.arange(-30000, 30000), 0, None).astype(np.int32).view(np.float32)
        y = tone.gamma(xs, gamma=g)
        assert np.all(np.diff(y) >= 0), f"gamma {g} steps back near {centre}"
        assert np.all((y >= 0) & (y <= 1))
