"""``lenslab convert`` keeps a 16-bit integer input 16-bit in PNG, PPM/PGM and TIFF outputs unless ``--bits``
says otherwise. The inputs are written by OpenCV and OpenImageIO, and the outputs' depth, channels and
code values are read back by them (never by lenslab's own reader)."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main

cv2 = pytest.importorskip("cv2")
oiio = pytest.importorskip("OpenImageIO")

RNG = np.random.default_rng(7)
RGB16 = RNG.integers(0, 65536, (9, 13, 3), dtype=np.uint16)
LA16 = RNG.integers(0, 65536, (9, 13, 2), dtype=np.uint16)
LA16[1:, :, 1] = 65535  # opaque, except the first row: partly transparent pixels, straight colour


def oiio_read(path):
    """(OpenImageIO's format name, channel names, samples as uint16) of ``path``, colour as the file stores
    it (straight beside alpha: OpenImageIO would otherwise premultiply it)."""
    config = oiio.ImageSpec()
    config.attribute("oiio:UnassociatedAlpha", 1)
    f = oiio.ImageInput.open(str(path), config)
    assert f is not None, oiio.geterror()
    try:
        spec = f.spec()
        return str(spec.format), tuple(spec.channelnames), f.read_image(oiio.UINT16)
    finally:
        f.close()


@pytest.fixture
def inputs(tmp_path):
    cv2.imwrite(str(tmp_path / "rgb16.png"), RGB16[..., ::-1])  # OpenCV stores BGR
    out = oiio.ImageOutput.create(str(tmp_path / "la16.png"))
    spec = oiio.ImageSpec(13, 9, 2, oiio.UINT16)
    spec.channelnames = ("Y", "A")
    spec.alpha_channel = 1
    spec.attribute("oiio:UnassociatedAlpha", 1)  # these samples are straight colour: stored as they are
    assert out.open(str(tmp_path / "la16.png"), spec)
    out.write_image(LA16)
    out.close()
    cv2.imwrite(str(tmp_path / "grey16.pgm"), RGB16[..., 0])
    cv2.imwrite(str(tmp_path / "rgb8.png"), (RGB16[..., ::-1] >> 8).astype(np.uint8))
    return tmp_path


@pytest.mark.parametrize("name, to, channels, codes", [
    ("rgb16.png", "png", ("R", "G", "B"), RGB16),
    ("la16.png", "png", ("Y", "A"), LA16),
    ("rgb16.png", "tiff", ("R", "G", "B"), RGB16),
    ("la16.png", "tiff", ("Y", "A"), LA16),
    ("grey16.pgm", "png", ("Y",), RGB16[..., :1]),
    ("rgb16.png", "ppm", ("R", "G", "B"), RGB16),
])
def test_16_bit_input_stays_16_bit(inputs, name, to, channels, codes):
    out = inputs / f"out.{to}"
    assert main(["convert", str(inputs / name), "--to", to, "-o", str(out), "-q"]) == 0
    fmt, names, samples = oiio_read(out)
    assert fmt == "uint16"
    assert len(names) == len(channels)
    if to != "ppm":  # PPM has no channel names
        assert names == channels
    # every 16-bit code comes back as it went in: decoding to float32 and encoding again loses nothing
    np.testing.assert_array_equal(samples, codes)


def test_16_bit_png_read_by_opencv(inputs):
    out = inputs / "out.png"
    assert main(["convert", str(inputs / "rgb16.png"), "--to", "png", "-o", str(out), "-q"]) == 0
    back = cv2.imread(str(out), cv2.IMREAD_UNCHANGED)
    assert back.dtype == np.uint16
    np.testing.assert_array_equal(back[..., ::-1], RGB16)


def test_bits_8_still_asks_for_8_bit(inputs):
    out = inputs / "out.png"
    assert main(["convert", str(inputs / "rgb16.png"), "--to", "png", "-o", str(out), "--bits", "8", "-q"]) == 0
    back = cv2.imread(str(out), cv2.IMREAD_UNCHANGED)[..., ::-1]
    assert back.dtype == np.uint8
    expected = np.rint(RGB16.astype(np.float64) * (255.0 / 65535.0))  # the same light in 8-bit codes
    # float32 decode/encode may round a code lying within 1e-6 of a half the other way: off by one at most
    assert np.abs(back.astype(np.int64) - expected).max() <= 1
    assert np.mean(back == expected) > 0.99


def test_8_bit_input_stays_8_bit(inputs):
    out = inputs / "out.png"
    assert main(["convert", str(inputs / "rgb8.png"), "--to", "png", "-o", str(out), "-q"]) == 0
    fmt, _, _ = oiio_read(out)
    assert fmt == "uint8"
    np.testing.assert_array_equal(cv2.imread(str(out), cv2.IMREAD_UNCHANGED),
                                  cv2.imread(str(inputs / "rgb8.png"), cv2.IMREAD_UNCHANGED))
