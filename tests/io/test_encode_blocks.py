"""Display files written a block at a time hold the codes of the whole image: straight colour
(PNG, integer TIFF) encoded by colour-science's sRGB inverse EOTF and rounded, alpha as coverage,
and TPDF dither drawn as one stream over the image. Read back by OpenImageIO (its own PNG and TIFF
readers, ``oiio:UnassociatedAlpha`` = 1: the stored codes as they are). Exact equality: the codes are
integers and each value is far from a rounding tie (random float32 values)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import lenslab.io as lio
from lenslab.io.encode import _BLOCK, NonFiniteWarning

oiio = pytest.importorskip("OpenImageIO")
colour = pytest.importorskip("colour")


def _codes(path, bits):
    config = oiio.ImageSpec()
    config.attribute("oiio:UnassociatedAlpha", 1)
    inp = oiio.ImageInput.open(str(path), config)
    assert inp is not None, oiio.geterror()
    pixels = np.asarray(inp.read_image("uint8" if bits == 8 else "uint16"))
    inp.close()
    return pixels


def _image(rng, h, w, c):
    """Premultiplied H x W x C float32 with alpha 0, > 1 and NaN among the pixels, and NaN and +-inf colour."""
    img = (rng.random((h, w, c), dtype=np.float32) * 1.2).astype(np.float32)
    img[..., -1] = rng.random((h, w), dtype=np.float32) * 1.3 - 0.1  # some alpha < 0 and > 1
    img[0, 0, -1] = np.nan
    img[0, 1, -1] = 0.0
    img[1, :3, -1] = 0.5
    with np.errstate(invalid="ignore"):
        img[..., :-1] *= np.clip(img[..., -1:], 0, None)  # premultiplied by the alpha as stored
    img[1, 0, 0], img[1, 1, 0], img[1, 2, 0] = np.nan, np.inf, -np.inf  # (alpha 0.5: kept when unpremultiplied)
    return img


def _straight64(img):
    """Straight colour (as PNG stores it) and alpha in [0, 1], transcribed: colour / alpha in float32
    where alpha > 0, 0 where it is 0 (NaN alpha is 0)."""
    a = np.clip(np.nan_to_num(img[..., -1:], nan=0.0), 0.0, 1.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        c = np.where(a > 0, img[..., :-1] / np.where(a > 0, a, 1), 0).astype(np.float32)
    return c.astype(np.float64), a.astype(np.float64)


def _round(v, maxval):
    v = np.clip(np.nan_to_num(v, nan=0.0, posinf=1.0, neginf=0.0), 0.0, 1.0)
    return np.floor(v * maxval + 0.5).astype(np.int64)


def _round_coverage(a, maxval):
    """Alpha codes: coverage * maxval rounded in float32, as lenslab's quantiser states it (alpha is
    not sRGB-encoded; at 16 bits float32's rounding of a * 65535 decides near-ties)."""
    a32 = np.clip(np.nan_to_num(a.astype(np.float32), nan=0.0), 0.0, 1.0)
    return np.floor(a32 * np.float32(maxval) + np.float32(0.5)).astype(np.int64)


def check_straight_codes(path, img, bits) -> None:
    """The codes of ``path`` (read by OpenImageIO) are colour-science's sRGB of ``img``'s straight colour,
    rounded, and its alpha as coverage."""
    maxval = (1 << bits) - 1
    straight, a = _straight64(img)
    expected_colour = _round(colour.models.eotf_inverse_sRGB(np.clip(np.nan_to_num(straight, nan=0.0, posinf=1.0,
                                                                                   neginf=0.0), 0, 1)), maxval)
    got = _codes(path, bits).astype(np.int64)
    assert np.array_equal(got[..., :-1], expected_colour)
    assert np.array_equal(got[..., -1:], _round_coverage(a, maxval))


@pytest.mark.parametrize("ext,opts,bits,c", [(".png", {"bits": 8}, 8, 4), (".png", {"bits": 16}, 16, 4),
                                             (".tif", {"sample_type": "uint8"}, 8, 4),
                                             (".tif", {"sample_type": "uint16"}, 16, 2)])
def test_straight_codes_are_colour_science_srgb_of_the_whole_image(tmp_path, ext, opts, bits, c):
    rng = np.random.default_rng(7)
    img = _image(rng, 301, 257, c)  # several blocks, an odd number of values
    assert img.size > 2 * _BLOCK
    path = tmp_path / f"out{ext}"
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        lio.write(path, img, **opts)
    check_straight_codes(path, img, bits)
    notes = [str(w.message) for w in caught if issubclass(w.category, NonFiniteWarning)]
    assert len(notes) == 1 and "1 NaN" in notes[0] and "1 +inf" in notes[0] and "1 -inf" in notes[0], notes


def test_dithered_png_draws_one_noise_stream_over_the_image(tmp_path):
    """TPDF dither as drawn for the whole colour array at once (two float32 draws of its size from
    NumPy's PCG64 seeded 0, the first minus the second, added to code * 255 before rounding), whatever
    the blocks the encoder works in: the 8-bit codes equal that transcription."""
    from lenslab import srgb

    rng = np.random.default_rng(3)
    img = _image(rng, 301, 257, 4)
    img[1, :3, 0] = 0.5  # (finite: the transcription below takes no NaN through srgb.encode)
    path = tmp_path / "d.png"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NonFiniteWarning)
        lio.write(path, img, bits=8, dither=True)
    straight, a = _straight64(img)
    x = srgb.encode(straight.astype(np.float32)) * np.float32(255)
    noise = np.random.default_rng(0)
    x += noise.random(x.shape, dtype=np.float32) - noise.random(x.shape, dtype=np.float32)
    expected = np.clip(np.floor(x + np.float32(0.5)), 0, 255).astype(np.int64)
    got = _codes(path, 8).astype(np.int64)
    assert np.array_equal(got[..., :-1], expected)
    assert np.array_equal(got[..., -1:], _round_coverage(a, 255))


def test_tone_mapped_rgba_keeps_alpha_and_maps_straight_colour():
    """Reinhard's x / (1 + x) (Reinhard et al. 2002, eq. 3) on the straight colour, premultiplied again;
    alpha clipped to [0, 1]. float32 kernels: 1e-6 relative."""
    from lenslab.tone import tonemap

    rng = np.random.default_rng(5)
    img = rng.random((64, 96, 4), dtype=np.float32) * 4
    img[..., -1] = rng.random((64, 96), dtype=np.float32) * 1.2
    out = tonemap(img, "reinhard")
    a = np.clip(img[..., -1:].astype(np.float64), 0, 1)
    s = np.where(a > 0, img[..., :-1] / np.where(a > 0, a, 1), 0)
    assert out.dtype == np.float32 and out.shape == img.shape
    assert np.array_equal(out[..., -1:], a.astype(np.float32))
    np.testing.assert_allclose(out[..., :-1], s / (1 + s) * a, rtol=1e-6, atol=1e-7)
