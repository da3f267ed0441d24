"""Tone mapping works a band of rows at a time, in the memory of an image its caller gives up: the
values are those of the published curves on the whole image, whatever the bands. Reinhard's
x / (1 + x) (Reinhard et al. 2002, eq. 3) on the straight colour, premultiplied again, and the auto
exposure's log-average (middle grey 0.18 over the positive luminances, Rec.709 weights 0.2126, 0.7152,
0.0722 of IEC 61966-2-1, the darkest and brightest percent left out) transcribed in float64; float32
kernels: 1e-6 relative. The repairs of bad values are counted over every band in one warning."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import lenslab.tone.mapping as mapping
from lenslab.tone import tonemap


@pytest.fixture
def small_bands(monkeypatch):
    """Bands of 8 rows (the smallest a band may be) on a 96 x 130 image: twelve bands."""
    monkeypatch.setattr(mapping, "BAND_VALUES", 8 * 130)


def _rgba(seed=5):
    rng = np.random.default_rng(seed)
    img = rng.random((96, 130, 4), dtype=np.float32) * 4
    img[..., -1] = rng.random((96, 130), dtype=np.float32) * 1.2
    img[..., :-1] *= np.clip(img[..., -1:], 0, 1)
    return img


def _straight(img):
    a = np.clip(img[..., -1:].astype(np.float64), 0, 1)
    return np.where(a > 0, img[..., :-1] / np.where(a > 0, a, 1), 0), a


def test_bands_give_the_curve_on_the_straight_colour(small_bands):
    img = _rgba()
    assert len(mapping._bands(img)) == 12
    given = img.copy()
    out = tonemap(given, "reinhard", 1.0, in_place=True)
    assert out is given
    s, a = _straight(img)
    s = s * 2.0
    np.testing.assert_allclose(out[..., :-1], s / (1 + s) * a, rtol=1e-6, atol=1e-7)
    assert np.array_equal(out[..., -1:], a.astype(np.float32))


def test_auto_exposure_of_an_image_with_alpha_comes_from_its_straight_colour(small_bands):
    img = _rgba(7)
    s, a = _straight(img)
    lum = s @ np.array([0.2126, 0.7152, 0.0722])
    # the covered pixels' straight colour, each counted by its coverage (docs/guide/tone.md), trimmed by
    # NumPy's weighted percentiles
    keep = (lum > 0) & (a[..., 0] > 0)
    logs, w = np.log2(lum[keep]), a[..., 0][keep].astype(np.float64)
    lo, hi = np.percentile(logs, [1, 99], weights=w, method="inverted_cdf")
    kept = (logs >= lo) & (logs <= hi)
    ev = np.log2(0.18 / 2.0 ** np.average(logs[kept], weights=w[kept]))
    out = tonemap(img.copy(), "reinhard", "auto", in_place=True)
    x = s * 2.0 ** ev
    np.testing.assert_allclose(out[..., :-1], x / (1 + x) * a, rtol=1e-5, atol=1e-7)


@pytest.mark.parametrize("c", [3, 4])
def test_repairs_are_counted_over_every_band_in_one_warning(small_bands, c):
    img = _rgba()[..., :c].copy()
    img[3, 5, 0] = np.nan      # band 0
    img[50, 7, 1] = -0.5       # band 6: a real negative, judged before its band is overwritten
    img[90, 9, 2] = np.inf     # band 11
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        out = tonemap(img, "reinhard", in_place=True)
    notes = [str(w.message) for w in caught]
    assert len(notes) == 1 and "1 NaN" in notes[0] and "1 +inf" in notes[0] and "1 negative" in notes[0], notes
    assert out[3, 5, 0] == 0 and out[50, 7, 1] == 0 and out[90, 9, 2] == (img[90, 9, 3] if c == 4 else 1)


def test_slight_negatives_in_several_bands_are_no_warning(small_bands):
    """A lossy codec's undershoot next to black (no lower than 2**-10) in three bands: tallied, not warned."""
    img = _rgba()[..., :3].copy()
    img[4, 4, 0] = img[44, 4, 1] = img[94, 4, 2] = -2.0 ** -11
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        tonemap(img, "reinhard", in_place=True)
    assert not caught
