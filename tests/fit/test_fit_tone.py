"""Tone matching: exposure and curve parameters recovered from an LDR made with known ones."""

from __future__ import annotations

import colour
import numpy as np
import pytest

from lenslab import tone
from lenslab.errors import FitError
from lenslab.fit.tone import ciede2000, fit_tone, sample_indices


@pytest.fixture(scope="module")
def hdr() -> np.ndarray:
    """A scene-linear image spanning about 12 stops (log-normal values), some of it above white."""
    rng = np.random.default_rng(7)
    return np.exp(rng.normal(-1.5, 1.6, (90, 120, 3))).astype(np.float32)


def quantise(display_linear: np.ndarray, bits: int) -> np.ndarray:
    """What a file of ``bits`` per sample holds, read back as linear light."""
    levels = 2 ** bits - 1
    enc = np.round(colour.cctf_encoding(display_linear, function="sRGB") * levels) / levels
    return colour.cctf_decoding(enc, function="sRGB").astype(np.float32)


@pytest.mark.parametrize("curve,truth", [
    ("hable", {"exposure": 0.7, "white": 8.0}),
    ("hable", {"exposure": -1.3, "white": 16.0}),
    ("reinhard-extended", {"exposure": -0.5, "white": 3.0}),
    ("gamma", {"exposure": 0.4, "gamma": 1.8}),
])
def test_known_parameters_are_recovered(hdr, curve, truth):
    params = {k: v for k, v in truth.items() if k != "exposure"}
    ldr = tone.tonemap(hdr, curve, truth["exposure"], **params)
    fit = fit_tone(hdr, ldr, curve)
    got = {"exposure": fit.exposure, **{k: fit.params[k] for k in params}}
    # an exact model on float data: the optimum is the truth to the optimiser's tolerance (1e-10 of
    # the range) and float32 rendering; 1e-3 is the required accuracy and leaves a wide margin
    for k, v in truth.items():
        assert got[k] == pytest.approx(v, abs=1e-3), k
    assert fit.rms_after < 1e-4 < fit.rms_before
    assert fit.delta_e_after["max"] < 0.05 < fit.delta_e_before["mean"]


def test_sixteen_bit_ldr_still_gives_parameters_within_a_thousandth(hdr):
    ldr = quantise(tone.tonemap(hdr, "hable", 0.7, white=8.0), 16)
    fit = fit_tone(hdr, ldr, "hable")
    # 16-bit quantisation noise (1/65535 per value) averaged over 10800 pixels moves the answer far less
    assert fit.exposure == pytest.approx(0.7, abs=1e-3) and fit.params["white"] == pytest.approx(8.0, abs=1e-3)


def test_eight_bit_ldr_reports_a_colour_difference_below_visibility(hdr):
    ldr = quantise(tone.tonemap(hdr, "hable", 0.7, white=8.0), 8)
    fit = fit_tone(hdr, ldr, "hable")
    # half a code of rounding (1/510 encoded) bounds what the fit can reach; the parameters come within
    # a few thousandths, and the CIEDE2000 after the fit is below 1 (a just-noticeable difference)
    assert fit.exposure == pytest.approx(0.7, abs=0.01)
    assert fit.rms_after < 1 / 255
    assert fit.delta_e_after["p95"] < 1.0 < fit.delta_e_before["mean"]


def test_luminance_mode_is_fitted_in_luminance_mode(hdr):
    ldr = tone.tonemap(hdr, "hable", 1.1, mode="luminance", white=6.0)
    fit = fit_tone(hdr, ldr, "hable", mode="luminance")
    assert fit.exposure == pytest.approx(1.1, abs=1e-3) and fit.params["white"] == pytest.approx(6.0, abs=1e-3)


def test_fixed_parameters_stay_and_free_names_are_honoured(hdr):
    ldr = tone.tonemap(hdr, "hable", 0.3, white=11.2, preset="gdc")
    fit = fit_tone(hdr, ldr, "hable", fixed={"preset": "gdc"}, free="exposure")
    assert fit.free == ("exposure",) and fit.params["white"] == 11.2 and fit.params["preset"] == "gdc"
    assert fit.exposure == pytest.approx(0.3, abs=1e-3)


def test_same_answer_twice(hdr):
    ldr = quantise(tone.tonemap(hdr, "reinhard-extended", 0.2, white=5.0), 8)
    a, b = fit_tone(hdr, ldr, "reinhard-extended"), fit_tone(hdr, ldr, "reinhard-extended")
    assert a.exposure == b.exposure and a.params == b.params and a.delta_e_after == b.delta_e_after


def test_ciede2000_of_known_colours():
    # identical colours differ by 0; white against black is L* 100 -> 0: CIEDE2000 gives exactly 100
    white, black = np.ones((1, 3)), np.zeros((1, 3))
    assert ciede2000(white, white)[0] == pytest.approx(0.0, abs=1e-9)
    assert ciede2000(white, black)[0] == pytest.approx(100.0, abs=1e-3)


def test_sample_indices_spread_over_the_image():
    idx = sample_indices(1000, 2000, 1 << 12)
    assert 3000 < len(idx) <= 1 << 12 and len(np.unique(idx)) == len(idx)
    rows, cols = idx // 2000, idx % 2000
    step = np.sqrt(1000 * 2000 / (1 << 12))  # 22 px between samples: every edge is within one step
    assert rows.min() < step and rows.max() > 1000 - step and cols.min() < step and cols.max() > 2000 - step
    assert np.array_equal(sample_indices(10, 10, 1 << 12), np.arange(100))


def test_errors_say_what_to_do(hdr):
    with pytest.raises(FitError, match="same view and size"):
        fit_tone(hdr, hdr[:10], "hable")
    with pytest.raises(FitError, match="unknown tone curve"):
        fit_tone(hdr, hdr, "sigmoid")
    with pytest.raises(FitError, match="no numeric parameter"):
        fit_tone(hdr, hdr, "hable", free="exposure,contrast")
    with pytest.raises(FitError, match="not fitted"):
        fit_tone(hdr, hdr, "hable", free="exposure", bounds="white=1:20")
