"""``mantiuk`` gives the same image for any exposure (its display mapping puts the scene's 0.1 to 99.9
percentiles on the display), so an exposure given to it is said to have no effect, in one note line.
Expected values: the image tone-mapped with exposure 0, and the arithmetic of the claim: ``x * 2**EV``
(float64 here) moves every percentile by the same factor, which the display mapping divides out."""

from __future__ import annotations

import subprocess
import sys
import warnings

import numpy as np
import pytest

import lenslab.io as lio
from lenslab.tone import ExposureIgnoredWarning, tonemap


def _image():
    return np.random.default_rng(3).lognormal(0, 2, (40, 48, 3)).astype(np.float32)


def _notes(**kwargs):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        out = tonemap(_image(), **kwargs)
    return out, [str(w.message) for w in caught if issubclass(w.category, ExposureIgnoredWarning)]


@pytest.mark.parametrize("exposure", [2.0, -1.5, "auto"])
def test_an_exposure_given_to_mantiuk_is_said_to_have_no_effect_and_has_none(exposure):
    out, notes = _notes(curve="mantiuk", exposure=exposure)
    assert notes == ["the exposure has no effect with tone curve mantiuk: it puts the scene's 0.1 to 99.9 "
                     "percentiles on the display whatever the exposure"]
    plain, none = _notes(curve="mantiuk")
    assert none == []
    # the same image: a power of two scales every value exactly, so the display mapping sees the same
    # log-luminance differences; what remains is OpenCV's float32 solve (1e-4 of a display in [0, 1])
    np.testing.assert_allclose(out, plain, rtol=0, atol=1e-4)


def test_curves_that_use_the_exposure_say_nothing():
    assert _notes(curve="hable", exposure=2.0)[1] == []
    assert _notes(curve="drago", exposure=2.0)[1] == []


def test_the_command_prints_one_note_line(tmp_path):
    src = tmp_path / "hdr.exr"
    lio.write(src, _image())
    run = subprocess.run([sys.executable, "-m", "lenslab", "tonemap", str(src), "-o", str(tmp_path / "t.png"),
                          "--curve", "mantiuk", "--exposure", "2"], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    notes = [line for line in run.stderr.splitlines() if "note:" in line]
    assert notes == ["lenslab tonemap: note: the exposure has no effect with tone curve mantiuk: it puts the "
                     "scene's 0.1 to 99.9 percentiles on the display whatever the exposure"]


@pytest.mark.parametrize("exposure", ["2", "auto"])
def test_the_summary_line_claims_no_stops_the_curve_did_not_use(tmp_path, exposure):
    """The summary of a mantiuk tone-map must not print "exposure +2.00 stops" (nor an "auto exposure"
    line) beside the note that the exposure has no effect: the PNG is byte for byte the one made without
    an exposure."""
    src = tmp_path / "hdr.exr"
    lio.write(src, _image())

    def run(out, *extra):
        done = subprocess.run([sys.executable, "-m", "lenslab", "tonemap", str(src), "-o", str(tmp_path / out),
                               "--curve", "mantiuk", "--no-dither", *extra], capture_output=True, text=True)
        assert done.returncode == 0, done.stderr
        return done.stderr.splitlines()

    lines = run("e.png", "--exposure", exposure)
    run("plain.png")
    assert (tmp_path / "e.png").read_bytes() == (tmp_path / "plain.png").read_bytes()
    assert not [line for line in lines if "stops" in line], lines
    assert f"{tmp_path / 'e.png'}: 48 x 40, curve mantiuk (a local operator on luminance), " \
           "the exposure has no effect" in lines
