"""OpenImageIO, as a compositor's reader and writer: every format lenslab writes, RGB and RGBA, every bit
depth. OIIO reads the colour and alpha lenslab meant; lenslab reads what OIIO writes.

What "meant" is, per format (docs/conventions.md): EXR and float TIFF store premultiplied linear colour;
PNG and 8/16-bit TIFF store straight colour sRGB-encoded (sRGB(colour / alpha)) with linear alpha, the
TIFF tagged ExtraSamples = 2; PPM/PGM sRGB-encoded; PFM and Radiance HDR linear floats. OIIO is asked for
the stored values as they are (``oiio:UnassociatedAlpha`` = 1: no premultiplication of its own).
"""

from __future__ import annotations

import numpy as np
import pytest

import lenslab.io as lio

oiio = pytest.importorskip("OpenImageIO")

H, W = 7, 11


def srgb_encode(x):
    """IEC 61966-2-1, transcribed in float64."""
    x = np.clip(np.asarray(x, np.float64), 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055)


def srgb_decode(v):
    v = np.asarray(v, np.float64)
    return np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4)


def premultiplied(c, seed=0):
    """A premultiplied image: straight colour in [0, 1] times alpha in [0, 1] (some 0 and some 1)."""
    rng = np.random.default_rng(seed)
    straight = rng.random((H, W, c - 1 if c in (2, 4) else c))
    if c not in (2, 4):
        return straight.astype(np.float32)
    a = rng.random((H, W, 1))
    a[0, :3] = 0.0
    a[1, :3] = 1.0
    return np.concatenate([straight * a, a], -1).astype(np.float32)


def straight_of(img):
    if img.shape[2] not in (2, 4):
        return img[..., :].astype(np.float64)
    a = img[..., -1:].astype(np.float64)
    return np.divide(img[..., :-1], a, out=np.zeros(img[..., :-1].shape), where=a > 0)


def oiio_read(path):
    config = oiio.ImageSpec()
    config.attribute("oiio:UnassociatedAlpha", 1)
    inp = oiio.ImageInput.open(str(path), config)
    assert inp is not None, oiio.geterror()
    spec = inp.spec()
    pixels = inp.read_image("float")
    inp.close()
    return np.asarray(pixels, np.float64).reshape(spec.height, spec.width, spec.nchannels), spec


#: (extension, lenslab write options, channel counts, bits)
DISPLAY = [(".png", {"bits": 8}, (1, 2, 3, 4), 8), (".png", {"bits": 16}, (1, 2, 3, 4), 16),
           (".tif", {"sample_type": "uint8"}, (1, 2, 3, 4), 8), (".tif", {"sample_type": "uint16"}, (1, 2, 3, 4), 16),
           (".ppm", {"bits": 8}, (3,), 8), (".ppm", {"bits": 16}, (3,), 16), (".pgm", {"bits": 8}, (1,), 8),
           (".pgm", {"bits": 16}, (1,), 16), (".jpg", {}, (1, 3), 8)]
DISPLAY_CASES = [(e, o, c, b) for e, o, cs, b in DISPLAY for c in cs]


@pytest.mark.parametrize("ext,options,c,bits", DISPLAY_CASES,
                         ids=[f"{e[1:]}{b}-{c}ch" for e, _, c, b in DISPLAY_CASES])
def test_oiio_reads_display_files_as_meant(tmp_path, ext, options, c, bits):
    img = premultiplied(c)
    path = lio.write(tmp_path / f"a{ext}", img, **options)
    got, spec = oiio_read(path)
    assert spec.nchannels == c
    maxval = 2 ** bits - 1
    colour = srgb_encode(straight_of(img))
    if ext == ".jpg":  # lossy: the codes OIIO decodes are those lenslab decodes (both libjpeg's IDCT)
        colour = lio.read(path, raw=True)[0].astype(np.float64)
    # integer codes: rounded to nearest, so within half a code of the exact value; OIIO gives code / maxval
    tol = 0.5 / maxval + 1e-6
    nc = c - 1 if c in (2, 4) else c
    assert np.abs(got[..., :nc] - colour).max() <= tol
    if c in (2, 4):
        assert np.abs(got[..., -1] - img[..., -1]).max() <= 0.5 / maxval + 1e-6  # alpha linear coverage
        if ext == ".tif":
            assert spec.get_int_attribute("tiff:ExtraSamples", -1) in (-1, 2)
            assert spec.get_int_attribute("oiio:UnassociatedAlpha") == 1  # OIIO saw unassociated alpha


FLOATS = [(".exr", {"pixel_type": "half"}, (1, 2, 3, 4), np.float16),
          (".exr", {"pixel_type": "float"}, (1, 2, 3, 4), np.float32),
          (".tif", {"sample_type": "float"}, (1, 2, 3, 4), np.float32),
          (".tif", {"sample_type": "half"}, (1, 2, 3, 4), np.float16),
          (".pfm", {}, (1, 3), np.float32)]
FLOAT_CASES = [(e, o, c, t) for e, o, cs, t in FLOATS for c in cs]


@pytest.mark.parametrize("ext,options,c,dtype", FLOAT_CASES,
                         ids=[f"{e[1:]}-{np.dtype(t).name}-{c}ch" for e, _, c, t in FLOAT_CASES])
def test_oiio_reads_float_files_exactly(tmp_path, ext, options, c, dtype):
    img = premultiplied(c) * np.float32(40.0)  # HDR values
    if c in (2, 4):
        img[..., -1] /= 40.0
    if ext == ".exr" and c == 2:
        options = {**options, "channels": ["Y", "A"]}
    path = lio.write(tmp_path / f"a{ext}", img, **options)
    got, spec = oiio_read(path)
    want = img.astype(dtype).astype(np.float64)  # a plain cast to the stored type: nothing else changes
    np.testing.assert_array_equal(got, want)
    if c in (2, 4) and ext == ".tif":
        # float TIFF alpha is associated (premultiplied colour, as EXR's): OIIO leaves it as it is
        assert spec.get_int_attribute("oiio:UnassociatedAlpha", 0) == 0


def test_oiio_reads_radiance_hdr_within_half_a_mantissa_step(tmp_path):
    img = premultiplied(3) * np.float32(100.0)
    got, _ = oiio_read(lio.write(tmp_path / "a.hdr", img))
    # lenslab writes Radiance's setcolr (truncated mantissas), OIIO decodes (m) 2^(E-136) without Radiance's
    # +0.5: each component within one mantissa step, 2^(E-136) <= max component / 128, of the value
    step = img.max(axis=-1, keepdims=True).astype(np.float64) / 128
    assert (np.abs(got - img) <= step * 1.0001).all()


# -- lenslab reads what OIIO writes ---------------------------------------------------------------

def oiio_write(path, pixels, fmt, unassociated=False):
    h, w, c = pixels.shape
    spec = oiio.ImageSpec(w, h, c, fmt)
    if unassociated:
        spec.attribute("oiio:UnassociatedAlpha", 1)
    out = oiio.ImageOutput.create(str(path))
    assert out is not None, oiio.geterror()
    assert out.open(str(path), spec), out.geterror()
    assert out.write_image(np.ascontiguousarray(pixels, np.float32)), out.geterror()
    out.close()


@pytest.mark.parametrize("ext,fmt,c", [(e, f, c) for e, f in [(".png", "uint8"), (".png", "uint16"), (".tif", "uint8"),
                                                              (".tif", "uint16"), (".ppm", "uint8"), (".ppm", "uint16")]
                                       for c in ((3,) if e == ".ppm" else (3, 4))])
def test_lenslab_reads_oiio_display_files(tmp_path, ext, fmt, c):
    rng = np.random.default_rng(5)
    stored = rng.random((H, W, c))  # the file's values: straight sRGB-encoded colour, linear alpha
    path = tmp_path / f"o{ext}"
    oiio_write(path, stored, fmt, unassociated=True)
    image, meta = lio.read(path)
    # the codes as OIIO reads its own file back (code / maxval). Not ``stored`` itself: OpenImageIO 3.2.2
    # writes PPM rows bottom to top (its own reader then shows them upside down), and rounds to 16 bits
    # in float32
    codes, _ = oiio_read(path)
    want = srgb_decode(codes[..., :3])
    if c == 4:
        want = want * codes[..., 3:]  # straight in the file, premultiplied in memory
        np.testing.assert_allclose(image[..., 3], codes[..., 3], atol=1e-7)
    # lenslab decodes by colour-science's float64 sRGB in a float32 table, then multiplies by alpha in
    # float32: two float32 roundings, 2 x 2^-24 = 1.2e-7 each side of the float64 value (4e-7 allowed)
    np.testing.assert_allclose(image[..., :3], want, rtol=4e-7, atol=1e-9)


@pytest.mark.parametrize("ext,fmt,c", [(e, f, c) for e, f in [(".exr", "half"), (".exr", "float"), (".tif", "float"),
                                                              (".tif", "half"), (".pfm", "float")]
                                       for c in ((3,) if e == ".pfm" else (3, 4))])
def test_lenslab_reads_oiio_float_files(tmp_path, ext, fmt, c):
    img = premultiplied(c, seed=6) * np.float32(20.0)
    if c == 4:
        img[..., -1] /= 20.0
    path = tmp_path / f"o{ext}"
    oiio_write(path, img, fmt)
    image, _ = lio.read(path)
    stored, _ = oiio_read(path)  # OIIO's float -> half rounding is its own: compare with what it stored
    np.testing.assert_array_equal(image, stored.astype(np.float32))
    np.testing.assert_allclose(image, img, rtol=2 ** -10 if fmt == "half" else 0)  # and that is the image
