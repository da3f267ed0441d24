"""A grey+alpha PNG (colour type 4) reads as two channels, grey and alpha, and `lenslab convert` and
`lenslab tonemap` write grey and alpha out: checked against what OpenImageIO, tifffile and OpenCV read, and
the sRGB decoding (IEC 61966-2-1) in float64 here."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from lenslab import io

oiio = pytest.importorskip("OpenImageIO")


def srgb_to_linear(v):
    v = np.asarray(v, np.float64)
    return np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4)


def _oiio_write(path, codes):
    out = oiio.ImageOutput.create(str(path))
    spec = oiio.ImageSpec(codes.shape[1], codes.shape[0], 2, "uint8" if codes.dtype == np.uint8 else "uint16")
    spec.channelnames = ("Y", "A")
    spec.alpha_channel = 1
    spec.attribute("oiio:UnassociatedAlpha", 1)  # the codes are straight already: store them as they are
    assert out.open(str(path), spec) and out.write_image(codes)
    out.close()


def _oiio_read(path):
    config = oiio.ImageSpec()
    config.attribute("oiio:UnassociatedAlpha", 1)  # the stored codes, not OpenImageIO's premultiplied reading
    inp = oiio.ImageInput.open(str(path), config)
    spec = inp.spec()
    pixels = inp.read_image(format=spec.format)
    inp.close()
    return spec, pixels


def _lenslab(*args):
    run = subprocess.run([sys.executable, "-m", "lenslab", *map(str, args)], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    return run


@pytest.fixture(params=[8, 16])
def grey_alpha(request, tmp_path):
    bits = request.param
    maxval = 2 ** bits - 1
    rng = np.random.default_rng(bits)
    codes = rng.integers(0, maxval + 1, (24, 33, 2)).astype(np.uint8 if bits == 8 else np.uint16)
    codes[0, :5, 1] = [0, 1, maxval // 2, maxval - 1, maxval]  # alpha's ends and middle
    path = tmp_path / f"la{bits}.png"
    _oiio_write(path, codes)  # written by OpenImageIO: colour type 4
    assert path.read_bytes()[25] == 4
    return path, codes, maxval


def test_reading_gives_grey_and_alpha(grey_alpha):
    path, codes, maxval = grey_alpha
    image, meta = io.read(path)
    assert image.shape == codes.shape and meta["channels"] == ["Y", "A"]
    alpha = codes[..., 1] / maxval
    expect = srgb_to_linear(codes[..., 0] / maxval) * alpha  # straight in the file, premultiplied in memory
    # float32 arithmetic on values <= 1: a few ulps
    np.testing.assert_allclose(image[..., 1], alpha, rtol=0, atol=2e-7)
    np.testing.assert_allclose(image[..., 0], expect, rtol=0, atol=1e-6)
    # OpenCV, the decoder lenslab uses, repeats the grey as B, G and R: the same grey and alpha
    import cv2

    bgra = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    assert np.array_equal(bgra[..., [0, 3]], codes) and np.array_equal(bgra[..., 1], bgra[..., 0])


def test_convert_to_png_keeps_the_two_channels_and_their_codes(grey_alpha, tmp_path):
    path, codes, maxval = grey_alpha
    out = tmp_path / "out.png"
    _lenslab("convert", path, "--to", "png", "--bits", 16 if maxval > 255 else 8, "-o", out)
    spec, got = _oiio_read(out)
    assert spec.nchannels == 2 and tuple(spec.channelnames) == ("Y", "A") and spec.alpha_channel == 1
    assert np.array_equal(got[..., 1], codes[..., 1])  # alpha: the same codes
    seen = codes[..., 1] > 0  # where alpha is 0 a straight colour is not kept (premultiplied memory holds 0)
    # premultiplying and unpremultiplying in float32 may move a 16-bit code by one where alpha is tiny
    tol = 0 if maxval == 255 else 1
    assert np.abs(got[..., 0].astype(np.int64) - codes[..., 0])[seen].max() <= tol


def test_convert_to_exr_and_tiff_write_grey_and_alpha(grey_alpha, tmp_path):
    path, codes, maxval = grey_alpha
    alpha = codes[..., 1] / maxval
    premultiplied = srgb_to_linear(codes[..., 0] / maxval) * alpha
    exr = tmp_path / "out.exr"
    _lenslab("convert", path, "--to", "exr", "--pixel-type", "float", "-o", exr)
    spec, got = _oiio_read(exr)
    assert tuple(spec.channelnames) == ("Y", "A")
    np.testing.assert_allclose(got[..., 0], premultiplied, rtol=0, atol=1e-6)  # EXR: premultiplied colour
    np.testing.assert_allclose(got[..., 1], alpha, rtol=0, atol=2e-7)
    import tifffile

    tif = tmp_path / "out.tif"
    _lenslab("convert", path, "--to", "tiff", "-o", tif)
    with tifffile.TiffFile(tif) as t:
        page = t.pages[0]
        pixels = page.asarray()
        assert pixels.shape == codes.shape and page.photometric.name == "MINISBLACK"
        if maxval == 65535:  # a 16-bit input stays 16-bit integers: straight alpha, the input's codes
            assert pixels.dtype == np.uint16 and [int(v) for v in page.extrasamples] == [2]
            covered = codes[..., 1] > 0  # where alpha is 0 lenslab's premultiplied image holds no colour: 0
            np.testing.assert_array_equal(pixels[..., 1], codes[..., 1])
            np.testing.assert_array_equal(pixels[..., 0][covered], codes[..., 0][covered])
            assert not pixels[..., 0][~covered].any()
            return
        assert [int(v) for v in page.extrasamples] == [1]  # associated alpha: float TIFF holds premultiplied
    np.testing.assert_allclose(pixels[..., 0], premultiplied, rtol=0, atol=1e-6)
    np.testing.assert_allclose(pixels[..., 1], alpha, rtol=0, atol=2e-7)


def test_tonemap_writes_grey_and_the_same_alpha(grey_alpha, tmp_path):
    path, codes, maxval = grey_alpha
    out = tmp_path / "toned.png"
    _lenslab("tonemap", path, "-o", out, "--bits", 16 if maxval > 255 else 8)
    spec, got = _oiio_read(out)
    assert spec.nchannels == 2 and tuple(spec.channelnames) == ("Y", "A")
    assert np.array_equal(got[..., 1], codes[..., 1])  # coverage is not a tone
