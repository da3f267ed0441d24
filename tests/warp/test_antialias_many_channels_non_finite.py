"""--antialias on an image of more than four channels (an EXR's extra layers) whose first channels hold NaN or inf
in places: the footprint kernel integrates four channels at a time, and a group whose texels are not all finite
reads each footprint through its own window; the next group of channels must go back to the footprints' shared
window (it read through the last footprint's window alone, out of bounds for the others: a crash).

Channels are filtered independently, so each channel of the many-channel warp is the warp of that channel
alone (the one-channel kernel), and the non-finite channels read NaN as 0 and inf as the largest float32, as the
engine says it does."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from lenslab.lenses import Camera
from lenslab.warp.engine import WarpPlan

SRC = Camera.from_spec("equirect", (64, 32))
DST = Camera.from_spec("fisheye:fov=180", (20, 20))


def _warp(image):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # the note on the non-finite source
        return WarpPlan(SRC, DST, antialias=True).run(image, alpha_channel=False)


@pytest.mark.parametrize("channels", [5, 8])
@pytest.mark.parametrize("bad", [np.nan, np.inf])
def test_finite_channels_after_non_finite_ones_are_each_channels_own_warp(channels, bad):
    image = np.random.default_rng(0).random((32, 64, channels), dtype=np.float32)
    image[10:22, 20:44, :4] = bad  # the first group of four channels only
    out, alpha = _warp(image)
    assert np.isfinite(out).all() and alpha.max() == 1.0
    for ch in range(4, channels):  # finite channels: what the one-channel kernel gives each alone
        # both sum the same float64 terms, in another order only: float32 rounding of the mean
        alone = _warp(np.ascontiguousarray(image[..., ch:ch + 1]))[0][..., 0]
        np.testing.assert_allclose(out[..., ch], alone, rtol=1e-6, atol=1e-7)
    fixed = image[..., :1].copy()
    fixed[10:22, 20:44] = 0.0 if np.isnan(bad) else np.finfo(np.float32).max
    want = _warp(fixed)[0][..., 0]
    np.testing.assert_allclose(out[..., 0], want, rtol=1e-6, atol=1e-7)
