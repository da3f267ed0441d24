"""Tone mapping in the memory of an image its caller gives up (``in_place=True``: ``lenslab convert`` to
a display format, ``lenslab tonemap``) gives the values of a separate output, bit for bit, for every
registered curve and both modes, with and without alpha; and Reinhard's x / (1 + x) (Reinhard et al.
2002, eq. 3) and Hable's filmic curve (Hable 2010, "Uncharted 2", A..F = 0.15, 0.50, 0.10, 0.20, 0.02,
0.30, exposure bias 2, white 11.2), transcribed in float64, within float32's rounding (1e-6 relative)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from lenslab.tone import CURVES, tonemap


def _scene(c, seed=0):
    rng = np.random.default_rng(seed)
    img = (rng.random((96, 130, c), dtype=np.float32) * 6).astype(np.float32)
    if c in (2, 4):
        img[..., -1] = rng.random((96, 130), dtype=np.float32) * 1.2
        img[..., :-1] *= np.clip(img[..., -1:], 0, 1)
    return img


@pytest.mark.parametrize("curve", list(CURVES))
@pytest.mark.parametrize("c,mode", [(3, "per-channel"), (3, "luminance"), (4, "per-channel"), (1, "per-channel")])
def test_in_place_gives_the_same_bits(curve, c, mode):
    img = _scene(c)
    img[0, 0, 0] = -1e-7  # a slight negative (repaired, tallied)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        expected = tonemap(img, curve, 0.5, mode)
        given = img.copy()
        got = tonemap(given, curve, 0.5, mode, in_place=True)
    assert np.array_equal(got, expected, equal_nan=True)
    assert got.dtype == np.float32 and got.shape == img.shape


@pytest.mark.parametrize("c", [3, 4])
def test_in_place_uses_the_given_memory(c):
    given = _scene(c)
    assert tonemap(given, "reinhard", in_place=True) is given
    kept = _scene(c)
    assert tonemap(kept, "reinhard") is not kept and np.array_equal(kept, _scene(c))  # the input untouched


@pytest.mark.parametrize("c", [3, 4])
def test_a_real_negative_is_judged_on_the_input_before_it_is_overwritten(c):
    """A negative beyond the slight ones needs the input to be judged (the warning): each band is judged
    before its memory takes the result, so the given memory still holds it and the values are those of
    the copy path; a codec's slight undershoot alone is no warning."""
    img = _scene(c)
    img[5, 5, 1] = -0.5 * (img[5, 5, -1] if c == 4 else 1)
    given = img.copy()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        expected = tonemap(img, "reinhard")
        got = tonemap(given, "reinhard", in_place=True)
    assert got is given and np.array_equal(got, expected)
    assert sum("negative" in str(w.message) for w in caught) == 2
    slight = _scene(c)
    slight[5, 5, 1] = -2.0 ** -11  # below the half-float step at 1.0: a codec's undershoot
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        tonemap(slight, "reinhard", in_place=True)
    assert not caught


def test_values_against_transcribed_curves():
    img = _scene(4, seed=3)
    a = np.clip(img[..., -1:].astype(np.float64), 0, 1)
    s = np.where(a > 0, img[..., :-1] / np.where(a > 0, a, 1), 0) * 2.0  # exposure +1 stop
    got = tonemap(img.copy(), "reinhard", 1.0, in_place=True)
    np.testing.assert_allclose(got[..., :-1], s / (1 + s) * a, rtol=1e-6, atol=1e-7)
    assert np.array_equal(got[..., -1:], a.astype(np.float32))

    rgb = _scene(3, seed=4).astype(np.float64)

    def hable(x, A=0.15, B=0.50, C=0.10, D=0.20, E=0.02, F=0.30):
        return ((x * (A * x + C * B) + D * E) / (x * (A * x + B) + D * F)) - E / F

    got = tonemap(_scene(3, seed=4), "hable", in_place=True)
    np.testing.assert_allclose(got, np.minimum(hable(2.0 * rgb) / hable(11.2), 1.0), rtol=1e-5, atol=1e-6)
