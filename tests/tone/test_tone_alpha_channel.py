"""``alpha_channel=``: tone mapping, exposure and the OpenColorIO display transform decide alpha by the
image's names where given (only ``A`` is alpha), else by 2 or 4 channels, as the warp APIs do
(:func:`lenslab.io.alpha.alpha_last`). Expected values: Reinhard's ``x / (1 + x)`` transcribed in float64,
and PyOpenColorIO's own processor."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.errors import FormatError
from lenslab.tone import auto_exposure, tonemap


def _reinhard(x):
    x = np.asarray(x, np.float64)
    return x / (1.0 + x)


def _image(c, seed=1):
    rng = np.random.default_rng(seed)
    return rng.uniform(0.05, 8.0, (5, 7, c)).astype(np.float32)


def test_four_data_channels_are_all_mapped_when_none_is_alpha():
    img = _image(4)  # R G B Z: the last is data, not coverage
    out = tonemap(img, "reinhard", alpha_channel=False)
    # float32 arithmetic of a division: a few ulp of values below 1
    np.testing.assert_allclose(out, _reinhard(img), rtol=0, atol=1e-6)


def test_rgba_by_count_maps_the_straight_colour_and_keeps_alpha():
    img = _image(4)
    img[..., 3] = np.linspace(0.1, 1.0, img[..., 3].size).reshape(img.shape[:2])
    img[..., :3] *= img[..., 3:]
    for alpha_channel in (None, True):
        out = tonemap(img, "reinhard", alpha_channel=alpha_channel)
        a = img[..., 3:].astype(np.float64)
        expected = _reinhard(img[..., :3] / a) * a  # the straight colour mapped, premultiplied again
        np.testing.assert_allclose(out[..., :3], expected, rtol=0, atol=1e-6)
        np.testing.assert_array_equal(out[..., 3], img[..., 3])


def test_two_data_channels_and_grey_with_named_alpha():
    uv = _image(2)
    np.testing.assert_allclose(tonemap(uv, "reinhard", alpha_channel=False), _reinhard(uv), rtol=0, atol=1e-6)
    # the default (no names): Y A
    ya = tonemap(uv, "reinhard")
    np.testing.assert_allclose(ya[..., 0], _reinhard(uv[..., 0] / np.clip(uv[..., 1], 0, 1)) * np.clip(uv[..., 1], 0, 1),
                               rtol=0, atol=1e-6)


def test_exposure_auto_weighs_data_channels_as_values_when_none_is_alpha():
    img = np.full((4, 4, 4), 0.5, np.float32)
    img[..., 3] = 2.0  # a fourth data channel (values exact in float32)
    # without alpha every value counts as grey: the geometric mean of 0.5, 0.5, 0.5, 2.0
    mean = 2.0 ** np.mean(np.log2([0.5, 0.5, 0.5, 2.0]))
    assert auto_exposure(img, trim=0, alpha_channel=False) == pytest.approx(np.log2(0.18 / mean), abs=1e-12)
    # with alpha (2.0 clipped to 1) the colour is grey 0.5 (sRGB weights sum to 1)
    assert auto_exposure(img, trim=0) == pytest.approx(np.log2(0.18 / 0.5), abs=1e-6)  # float32 weights: sum 1 to 1e-7


def test_display_transform_takes_alpha_from_the_caller():
    ocio = pytest.importorskip("PyOpenColorIO")
    from lenslab.io.ocio import display_transform

    img = _image(4, seed=3)
    cfg = ocio.Config.CreateFromFile("ocio://default")
    proc = cfg.getProcessor("Linear Rec.709 (sRGB)", "sRGB - Display", "Un-tone-mapped",
                            ocio.TRANSFORM_DIR_FORWARD).getDefaultCPUProcessor()
    ref = np.ascontiguousarray(img[..., :3]).copy()
    proc.applyRGB(ref)
    out = display_transform(img, "sRGB - Display", "Un-tone-mapped", alpha_channel=True)
    np.testing.assert_allclose(out[..., :3], ref, rtol=0, atol=1e-5)  # the same float32 processor
    np.testing.assert_array_equal(out[..., 3], img[..., 3])
    with pytest.raises(FormatError, match="4 colour channels"):  # R G B Z: no display colour for Z
        display_transform(img, "sRGB - Display", "Un-tone-mapped", alpha_channel=False)
    grey = np.ascontiguousarray(np.repeat(img[..., :1], 3, -1))
    proc.applyRGB(grey)
    ya = display_transform(img[..., :2], "sRGB - Display", "Un-tone-mapped", alpha_channel=True)
    np.testing.assert_allclose(ya[..., 0], grey[..., 0], rtol=0, atol=1e-5)
    np.testing.assert_array_equal(ya[..., 1], img[..., 1])


def test_develop_reads_alpha_from_the_channel_names():
    from lenslab.io.registry import get
    from lenslab.io import carries_alpha
    from lenslab.jobs.stages import Look, develop

    assert carries_alpha({"channels": ["R", "G", "B", "Z"]}, 4) is False
    assert carries_alpha({"channels": ["Z"]}, 2) is True  # a warp's coverage added as A
    assert carries_alpha({}, 4) is True
    img = _image(4)
    out, _ = develop(img, {"channels": ["u", "v", "w", "A"]}, get("exr"), Look(exposure=1.0))
    np.testing.assert_allclose(out[..., :3], img[..., :3].astype(np.float64) * 2.0, rtol=0, atol=0)
    np.testing.assert_array_equal(out[..., 3], img[..., 3])
