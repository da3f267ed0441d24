"""Bad input (NaN, inf, negatives), automatic exposure, luminance mode, alpha, and error messages."""

from __future__ import annotations

import warnings

import cv2
import numpy as np
import pytest

from lenslab import tone
from lenslab.errors import ToneError


def recorded(fn):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        out = fn()
    return out, [w.message for w in caught if isinstance(w.message, tone.ToneWarning)]


@pytest.mark.parametrize("mode", ["per-channel", "luminance"])
@pytest.mark.parametrize("name", ["clamp", "hable", "aces-hill", "pbr-neutral"])
def test_nan_inf_negative_are_repaired_counted_and_warned(name, mode):
    img = np.full((4, 5, 3), 0.25, np.float32)
    img[0, 0, 0] = np.nan
    img[0, 1, 1] = np.nan
    img[1, 0, 2] = np.inf
    img[2, 0, 0] = -0.5
    img[2, 1, 1] = -np.inf
    img[2, 2, 2] = -1e-30
    out, warns = recorded(lambda: tone.tonemap(img, name, mode=mode))
    assert len(warns) == 1
    w = warns[0]
    assert (w.nan, w.posinf, w.negative, w.total) == (2, 1, 3, img.size)
    assert "2 NaN" in str(w) and "1 +inf" in str(w) and "3 negative" in str(w)
    assert np.all(np.isfinite(out)) and out.min() >= 0 and out.max() <= 1
    clean = img.copy()
    clean[~np.isfinite(clean) | (clean < 0)] = 0
    ref = tone.tonemap(clean, name, mode=mode)
    if mode == "per-channel" and name in ("clamp", "hable"):
        assert out[1, 0, 2] == 1.0                      # +inf -> white in that channel
        assert out[0, 0, 0] == 0 and out[2, 0, 0] == 0  # NaN and negative -> 0
    else:
        np.testing.assert_array_equal(out[1, 0], [1, 1, 1])  # +inf: the pixel is white
    untouched = np.ones(img.shape[:2], bool)
    untouched[1, 0] = False
    np.testing.assert_array_equal(out[untouched], ref[untouched])


def test_clean_input_gives_no_warning():
    img = np.random.default_rng(0).random((8, 8, 3), dtype=np.float32) * 10
    _, warns = recorded(lambda: tone.tonemap(img, "hable", exposure="auto"))
    assert warns == []


def test_local_operators_repair_too():
    img = np.random.default_rng(1).random((16, 16, 3), dtype=np.float32) + 0.1
    img[3, 3, 1] = np.nan
    img[4, 4, 0] = np.inf
    out, warns = recorded(lambda: tone.tonemap(img, "drago"))
    assert (warns[0].nan, warns[0].posinf) == (1, 1)
    assert np.all(np.isfinite(out)) and np.all(out[4, 4] == 1)


@pytest.mark.parametrize("name", list(tone.CURVES))
def test_black_image_with_auto_exposure_stays_black(name):
    black = np.zeros((8, 8, 3), np.float32)
    assert tone.auto_exposure(black) == 0.0
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no division warning, no repair warning
        out = tone.tonemap(black, name, exposure="auto")
    assert out.dtype == np.float32 and np.all(out == 0)


def test_auto_exposure_ignores_a_small_sun():
    rng = np.random.default_rng(2)
    scene = (0.05 * np.exp2(rng.normal(0, 1.5, (128, 256)))).astype(np.float32)
    img = np.repeat(scene[..., None], 3, axis=2)
    img[10:14, 100:104] = 30000.0  # 16 pixels of 32768: under the 1% trimmed at the top
    ev = tone.auto_exposure(img)
    # the scene's own log-average is 0.05 (lognormal around it): middle grey needs log2(0.18/0.05)
    assert ev == pytest.approx(np.log2(0.18 / 0.05), abs=0.1)  # 0.1 stop: sampling of 32768 draws
    out = tone.tonemap(img, "hable", exposure="auto")
    rest = np.ones(img.shape[:2], bool)
    rest[10:14, 100:104] = False
    assert np.median(out[rest]) > 0.05  # the scene is visible, not crushed to black
    assert np.all(out[10:14, 100:104] == 1.0)
    # what normalising by the maximum does instead (OpenCV's plain createTonemap): the scene is black
    by_max = cv2.createTonemap(1.0).process(img)
    assert np.median(by_max[rest]) < 1e-4


def test_exposure_parsing_and_range():
    x = np.float32([0.1, 0.5])
    np.testing.assert_array_equal(tone.tonemap(x, "clamp", exposure="1"), tone.tonemap(x, "clamp", exposure=1.0))
    np.testing.assert_allclose(tone.tonemap(x, "clamp", exposure=1.0), [0.2, 1.0])
    with pytest.raises(ToneError, match="auto"):
        tone.tonemap(x, "clamp", exposure="bright")
    with pytest.raises(ToneError, match=r"\[-100, 100\]"):
        tone.tonemap(x, "clamp", exposure=500)


def test_luminance_mode_preserves_channel_ratios_where_not_clipped():
    rng = np.random.default_rng(4)
    img = (rng.random((32, 32, 3)) * 0.6 + 0.01).astype(np.float32)
    for name in ("reinhard", "hable", "aces", "agx", "pbr-neutral"):
        out = tone.tonemap(img, name, mode="luminance")
        fine = out.max(axis=2) < 0.999
        assert fine.mean() > 0.9
        ratio = out[fine] / img[fine]
        # the same factor on every channel: float32 products, 1e-5 relative
        np.testing.assert_allclose(ratio, ratio[:, :1].repeat(3, axis=1), rtol=1e-5)
        # and that factor is curve(L) / L with Rec.709 luminance
        w = np.array([0.2126, 0.7152, 0.0722])
        lum = img[fine] @ w
        expected = tone.tonemap(lum.astype(np.float32), name) / lum
        np.testing.assert_allclose(ratio[:, 0], expected, rtol=2e-5)  # L itself is float32-rounded


def test_luminance_mode_over_range_keeps_luminance_and_blends_to_white():
    img = np.float32([[[50.0, 0.5, 0.5]]])  # luminance 11.3: a saturated red far past white
    out = tone.tonemap(img, "reinhard", mode="luminance")[0, 0]
    w = tone.luminance_weights()
    lum = float(img[0, 0] @ w)
    assert out.max() == pytest.approx(1.0, abs=1e-6)
    assert float(out @ w) == pytest.approx(lum / (1 + lum), rel=1e-5)  # luminance as the curve says
    assert out[0] > out[1] == pytest.approx(out[2])  # still red, less saturated


def test_luminance_weights_come_from_colour_science():
    np.testing.assert_allclose(tone.luminance_weights(), [0.2126, 0.7152, 0.0722], atol=1e-6)
    np.testing.assert_allclose(tone.luminance_weights("ITU-R BT.2020"), [0.2627, 0.6780, 0.0593], atol=1e-4)
    rec709 = ((0.64, 0.33), (0.30, 0.60), (0.15, 0.06), (0.3127, 0.3290))
    np.testing.assert_allclose(tone.luminance_weights(rec709), [0.2126, 0.7152, 0.0722], atol=2e-4)
    with pytest.raises(ToneError, match="colourspace"):
        tone.luminance_weights("no-such-space")


def test_alpha_passes_through_and_colour_is_unpremultiplied():
    img = np.zeros((1, 2, 4), np.float32)
    img[0, 0] = [0.25, 0.25, 0.25, 0.5]  # premultiplied: colour 0.5 at half coverage
    img[0, 1] = [0.0, 0.0, 0.0, 0.0]
    out = tone.tonemap(img, "reinhard")
    assert out.shape == img.shape and out[0, 0, 3] == 0.5
    np.testing.assert_allclose(out[0, 0, :3], 0.5 * (0.5 / 1.5), rtol=1e-6)
    assert np.all(out[0, 1] == 0)


def test_unknown_curve_lists_every_valid_name():
    with pytest.raises(ToneError) as err:
        tone.tonemap(np.zeros(3, np.float32), "filmic-ish")
    for name in tone.CURVES:
        assert name in str(err.value)
    assert tone.get_curve("Reinhard_Extended").name == "reinhard-extended"


def test_bad_parameters_say_what_is_valid():
    x = np.float32([0.5])
    with pytest.raises(ToneError, match=r"white=-1 is out of range.*\(0, 1e\+06\]"):
        tone.tonemap(x, "hable", white=-1)
    with pytest.raises(ToneError, match="exposure_bias=.*white=11.2") as err:
        tone.tonemap(x, "hable", whitepoint=4)
    assert "'whitepoint'" in str(err.value)
    with pytest.raises(ToneError, match="one of blog, gdc"):
        tone.tonemap(x, "hable", preset="film")
    with pytest.raises(ToneError, match="not a number"):
        tone.tonemap(x, "reinhard-extended", white="bright")
    with pytest.raises(ToneError, match="takes no parameters"):
        tone.tonemap(x, "aces", white=3)
    with pytest.raises(ToneError, match="not monotonic"):
        tone.tonemap(x, "hable", E=0.2)  # E > C*F = 0.03: the toe would dip below 0
    with pytest.raises(ToneError, match="per-channel"):
        tone.tonemap(x, "hable", mode="chroma")
    with pytest.raises(ToneError, match="channels"):
        tone.tonemap(np.zeros((2, 2, 5), np.float32), "hable")


def test_drago_matches_opencv_when_nothing_is_clipped():
    # (mantiuk keeps OpenCV's reconstruction but not its final stretch: tests/tone/test_mantiuk_display.py)
    rng = np.random.default_rng(5)
    img = (0.2 * np.exp2(rng.normal(0, 1, (24, 32, 3)))).astype(np.float32)  # < 12 stops of range
    ref = cv2.createTonemapDrago(1.0, 0.8, 0.85).process(img.copy())
    np.testing.assert_allclose(tone.drago(img, saturation=0.8), ref, atol=1e-6)  # the same float32 code


@pytest.mark.parametrize("name", ["drago", "mantiuk"])
def test_local_operators_on_grey_images_equal_the_colour_result(name):
    rng = np.random.default_rng(7)
    grey = (0.2 * np.exp2(rng.normal(0, 1, (16, 20, 1)))).astype(np.float32)
    out = tone.tonemap(grey, name)
    assert out.shape == grey.shape
    colour = tone.tonemap(np.repeat(grey, 3, axis=2), name)
    # OpenCV's Rec.601 luma of equal channels is the channel to float32 rounding
    np.testing.assert_allclose(out[..., 0], colour.mean(axis=2), atol=1e-5)


def test_drago_headroom_keeps_a_sun_from_crushing_the_scene():
    rng = np.random.default_rng(6)
    img = (0.2 * np.exp2(rng.normal(0, 1, (64, 64, 3)))).astype(np.float32)
    img[5:7, 5:7] = 30000.0
    ours = tone.drago(img)
    plain = np.nan_to_num(cv2.createTonemapDrago(1.0, 1.0, 0.85).process(img.copy()))
    assert np.median(ours) > 2 * np.median(plain)


@pytest.mark.parametrize("name", ["clamp", "hable", "agx"])
def test_luminance_mode_gives_a_pixel_the_same_bits_beside_a_bad_value_and_on_any_thread_count(name):
    # a block holding a NaN takes the repairing pass, a clean block the vectorised one (lenslab.tone.luminance):
    # a clean pixel's value must not depend on which its block took, nor on how the rows are split
    rng = np.random.default_rng(3)
    img = (0.18 * np.exp2(rng.normal(0.0, 3.0, (300, 200, 3)))).astype(np.float32)  # 60000 px: 3 blocks
    img[::37, ::11, 1] *= 40  # saturated bright pixels: the blend toward grey
    dirty = img.copy()
    for r in (0, 120, 299):
        dirty[r, 5, 0] = np.nan
    clean_out = tone.tonemap(img, name, mode="luminance", threads=1)
    dirty_out, warns = recorded(lambda: tone.tonemap(dirty, name, mode="luminance", threads=2))
    assert len(warns) == 1 and warns[0].nan == 3
    keep = np.ones(img.shape[:2], bool)
    keep[[0, 120, 299], 5] = False
    np.testing.assert_array_equal(dirty_out[keep], clean_out[keep])
    # and the values are the definition's: Ld = curve(L), RGB scaled by Ld / L, blended toward grey where
    # the brightest channel passes 1 (float64 here; float32 steps in the code: 1e-5 covers their rounding)
    w = tone.luminance_weights().astype(np.float64)
    x = img.astype(np.float64)
    lum = x @ w
    ld = tone.tonemap(lum.astype(np.float32)[..., None], name)[..., 0].astype(np.float64)
    c = x * (ld / lum)[..., None]
    peak = c.max(axis=-1)
    t = np.clip((1 - ld) / np.maximum(peak - ld, 1e-37), 0, 1)[..., None]
    ref = np.where(peak[..., None] > 1, np.clip(ld[..., None] + (c - ld[..., None]) * t, 0, 1), c)
    np.testing.assert_allclose(clean_out, ref, rtol=1e-5, atol=1e-5)


@pytest.mark.parametrize("name", [n for n in tone.CURVES if tone.get_curve(n).kind != "local"])
def test_luminance_mode_numpy_and_compiled_passes_give_the_same_bits(name, monkeypatch):
    # a one-image command runs NumPy's ufuncs, a process with numba loaded the compiled passes
    # (lenslab.tone.sweep.compiled_ready): the same float32 steps in the same order, so the same bits,
    # on bright saturated pixels, black, -0.0, NaN, +inf, negatives and the top of float32
    import lenslab.tone.sweep as sweep

    rng = np.random.default_rng(0)
    img = (0.18 * np.exp2(rng.normal(0.0, 3.0, (300, 200, 3)))).astype(np.float32)
    img[::37, ::11, 1] *= 40
    img[5, 5] = -0.0
    img[6, 6] = 0.0
    img[7, 7, 0] = np.nan
    img[8, 8, 2] = np.inf
    img[9, 9, 1] = -3.0
    img[10, 10] = [3e38, 1.0, 1.0]
    runs = {}
    for compiled in (True, False):
        monkeypatch.setattr(sweep, "COMPILED_PASSES", compiled)
        runs[compiled], warns = recorded(lambda: tone.tonemap(img, name, mode="luminance", threads=2))
        assert (warns[0].nan, warns[0].posinf, warns[0].negative) == (1, 1, 1)
    np.testing.assert_array_equal(runs[True].view(np.uint32), runs[False].view(np.uint32))
