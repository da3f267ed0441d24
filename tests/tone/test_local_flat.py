"""OpenCV's Mantiuk operator on an image without contrast: no cv2.error, a flat image in, a flat image out."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab import tone

pytest.importorskip("cv2")

REC601 = np.array([0.299, 0.587, 0.114])  # the luma OpenCV's operators take (ITU-R BT.601)


@pytest.mark.parametrize("value", [1e-3, 0.5, 3.0, 30000.0])
def test_flat_grey_maps_to_flat_mid_grey(value):
    out = tone.tonemap(np.full((16, 16, 3), value, np.float32), "mantiuk")
    assert out.dtype == np.float32 and np.all(out == 0.5)
    assert np.all(tone.tonemap(np.full((8, 8, 1), value, np.float32), "mantiuk") == 0.5)


@pytest.mark.parametrize("saturation", [0.5, 1.0, 1.5])
def test_flat_colour_keeps_its_colour_as_mantiuk_maps_colour(saturation):
    colour = np.array([0.6, 0.3, 0.1])
    out = tone.tonemap(np.full((16, 16, 3), colour, np.float32), "mantiuk", saturation=saturation)
    assert np.all(out == out[0, 0])  # flat
    # Mantiuk's colour: (c / L)^saturation times the new luminance (0.5), L the Rec.601 luma
    want = np.clip(0.5 * (colour / (colour @ REC601)) ** saturation, 0, 1)
    np.testing.assert_allclose(out[0, 0], want, rtol=1e-5)  # float32 steps against float64


def test_black_and_contrast_still_go_through_opencv():
    assert np.all(tone.tonemap(np.zeros((8, 8, 3), np.float32), "mantiuk") == 0)
    ramp = np.repeat(np.geomspace(0.01, 100.0, 16, dtype=np.float32)[None, :, None], 3, axis=2)
    y = tone.tonemap(np.repeat(ramp, 4, axis=0), "mantiuk")
    assert float(y.max()) == 1.0 and float(y.min()) >= 0.0  # OpenCV's stretch to [0, 1]
