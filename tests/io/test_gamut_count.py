"""The count and the clip of colours outside the gamut, against the definition written here in float64: a pixel
is outside when one of its three colour components is below -EDGE times the largest magnitude of the three (NaN
is neither; EDGE is the conversion's rounding, ``lenslab.io.colour.gamut.EDGE``), the clip sets those components to
0 and leaves alpha (even a negative one, from a hostile file) and NaN as they were. Images taller than a band
(256 rows), with alpha, with an extra channel of negatives (depth or a normal), and not contiguous."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from lenslab.io.colour.gamut import BAND_ROWS, EDGE, clip_outside, negative_pixels, outside


def _image(channels: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    image = rng.uniform(-0.05, 1.0, (BAND_ROWS + 45, 37, channels)).astype(np.float32)
    image[:BAND_ROWS, :, :3] = np.abs(image[:BAND_ROWS, :, :3])  # the first band: no colour outside
    image[BAND_ROWS + 3, 4, 1] = np.nan
    return image


@pytest.mark.parametrize("channels", [3, 4, 5])
def test_the_count_is_the_definition(channels):
    image = _image(channels, channels)
    image[5 + BAND_ROWS, 5, :3] = [1.0, -0.5 * EDGE, 0.5]  # within the edge: not outside
    image[6 + BAND_ROWS, 5, :3] = [1.0, -2.0 * EDGE, 0.5]  # past it: outside
    colours = image[..., :3].astype(np.float64)
    low, high = np.nanmin(colours, axis=-1), np.nanmax(colours, axis=-1)
    want = int(np.count_nonzero(low < -EDGE * np.maximum(high, -low)))
    assert want > 0
    assert outside(image) == want
    assert outside(image[::-1]) == want  # a view in another memory order
    assert outside(np.asfortranarray(image)) == want
    assert negative_pixels(image) == int(np.count_nonzero((colours < 0).any(axis=-1)))  # however little


@pytest.mark.parametrize("alpha", [False, True])
def test_the_clip_sets_negative_colour_to_zero_and_keeps_alpha(alpha):
    image = _image(4 if alpha else 3, 9)
    if alpha:
        image[7, 7, 3] = -0.5  # a hostile alpha: not the clip's business
    want = image.astype(np.float64)
    want[..., :3] = np.where(want[..., :3] < 0, 0.0, want[..., :3])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        out = clip_outside(image, {"wide_gamut": "ICC profile 'Display P3'"}, alpha)
    assert out is not image  # the caller's image stays its own (in_place not given)
    np.testing.assert_array_equal(out.astype(np.float64), want)
    count = f"{outside(image)} of {image.shape[0] * image.shape[1]} pixels"
    assert len(caught) == 1 and count in str(caught[0].message)
