"""Round trips through every format, and the sRGB encoding and atomic writes they rely on."""

from __future__ import annotations

import colour
import numpy as np
import pytest

import lenslab.io as lio
from lenslab.io.encode import decode_srgb, encode_quantise


def asym(h: int = 37, w: int = 53, c: int = 3, scale: float = 1.0, seed: int = 0) -> np.ndarray:
    """An image whose every pixel differs (catches flips, transposes and channel swaps)."""
    rng = np.random.default_rng(seed)
    return (rng.random((h, w, c)) * scale).astype(np.float32)


def test_pfm_bit_exact(tmp_path):
    img = asym(scale=1e4) - 5.0  # negatives and large values: PFM keeps any float32
    for order in ("little", "big"):
        p = lio.write(tmp_path / f"a_{order}.pfm", img, byte_order=order)
        back, meta = lio.read(p)
        assert back.dtype == np.float32 and back.flags.c_contiguous
        np.testing.assert_array_equal(back, img)
        assert meta["attributes"]["byte_order"] == order and meta["attributes"]["scale"] == 1.0


def test_pfm_grey_and_scale_kept_not_applied(tmp_path):
    img = asym(c=1)
    p = lio.write(tmp_path / "g.pfm", img, scale=4.0)
    data = p.read_bytes()
    assert data.startswith(b"Pf\n53 37\n-4.0") and data.index(b"\n", 9) + 1 == 64  # pixels start aligned
    assert float(data[9:64]) == -4.0 and len(data) == 64 + 53 * 37 * 4
    back, meta = lio.read(p)
    np.testing.assert_array_equal(back, img)  # the scale is recorded, never multiplied in
    assert meta["attributes"]["scale"] == 4.0 and meta["channels"] == ["Y"]


def test_pfm_rows_bottom_to_top(tmp_path):
    img = asym(h=3, w=2)
    p = lio.write(tmp_path / "o.pfm", img)
    data = p.read_bytes()
    payload = np.frombuffer(data[-2 * 3 * 3 * 4:], "<f4").reshape(3, 2, 3)
    np.testing.assert_array_equal(payload, img[::-1])  # first stored row is the bottom one


def test_exr_float_bit_exact(tmp_path):
    img = asym(c=4, scale=1e6) - 100.0
    p = lio.write(tmp_path / "f.exr", img, pixel_type="float")
    back, meta = lio.read(p)
    np.testing.assert_array_equal(back, img)
    assert meta["sample_type"] == "float" and meta["channels"] == ["R", "G", "B", "A"]


def test_exr_half_within_half_precision(tmp_path):
    img = asym(scale=1000.0)
    back, meta = lio.read(lio.write(tmp_path / "h.exr", img))
    # half has an 11-bit significand: round-to-nearest errs by at most 2^-11 relative (plus denormal step)
    np.testing.assert_allclose(back, img, rtol=2.0 ** -11, atol=2.0 ** -24)
    np.testing.assert_array_equal(back, img.astype(np.float16).astype(np.float32))
    assert meta["sample_type"] == "half" and meta["bit_depth"] == 16


@pytest.mark.parametrize("compression", ["none", "rle", "zips", "zip", "piz", "zstd", "htj2k256"])
def test_exr_lossless_compressions(tmp_path, compression):
    img = asym(c=3, scale=3.0)
    back, meta = lio.read(lio.write(tmp_path / "c.exr", img, pixel_type="float", compression=compression))
    np.testing.assert_array_equal(back, img)
    expected = "NO_COMPRESSION" if compression == "none" else f"{compression.upper()}_COMPRESSION"
    assert meta["attributes"]["compression"] == expected


def test_exr_half_overflow_clamped_and_counted(tmp_path):
    img = np.array([[[1e5, -7e4, 1.0], [np.inf, np.nan, 65504.0]]], np.float32)
    with pytest.warns(lio.HalfOverflowWarning, match="^2 value"):
        p = lio.write(tmp_path / "o.exr", img)
    back, _ = lio.read(p)
    assert back[0, 0, 0] == 65504.0 and back[0, 0, 1] == -65504.0
    assert np.isposinf(back[0, 1, 0]) and np.isnan(back[0, 1, 1])  # not out of range: kept
    assert issubclass(lio.HalfOverflowWarning, UserWarning)


def test_exr_strided_input_written_correctly(tmp_path):
    big = asym(h=40, w=60, c=4)
    view = big[::2, ::-3, [2, 0, 1]]  # non-contiguous, negative strides, reordered channels
    back, _ = lio.read(lio.write(tmp_path / "s.exr", view, pixel_type="float"))
    np.testing.assert_array_equal(back, view)


def test_exr_camera_round_trip(tmp_path):
    from lenslab.lenses import Camera

    cam = Camera.from_spec("perspective:fov=70", (53, 37), yaw=12.5, pitch=-3.0)
    p = lio.write(tmp_path / "cam.exr", asym(), camera=cam)
    _, meta = lio.read(p)
    got = meta["camera"]
    assert got.lens.spec() == cam.lens.spec() and got.lens.width == 53 and got.lens.height == 37
    xy = np.array([[0.5, 0.5], [26.5, 18.5], [52.5, 36.5]])
    # the pose goes through yaw/pitch/roll text and back: equal to float64 rounding
    np.testing.assert_allclose(got.pixel_to_world(xy)[1], cam.pixel_to_world(xy)[1], atol=1e-12)
    assert meta["attributes"]["lenslab.camera"] == cam.to_toml()
    _, meta = lio.read(lio.write(tmp_path / "nocam.exr", asym()))
    assert meta["camera"] is None
    p = lio.write(tmp_path / "badcam.exr", asym(), attributes={"lenslab.camera": "[lens]\nmodel = 'nosuch'\n"})
    with pytest.warns(lio.CameraAttributeWarning, match="nosuch|model|lens"):
        img, meta = lio.read(p)
    assert meta["camera"] is None and img.shape == (37, 53, 3)  # the pixels still read


def test_ppm_16bit_bit_exact(tmp_path):
    codes = np.random.default_rng(1).integers(0, 65536, (21, 34, 3)).astype(np.uint16)
    img = codes.astype(np.float32) / 65535  # raw code values: exactly representable round trip
    p = lio.write(tmp_path / "a.ppm", img, bits=16, raw=True)
    assert p.read_bytes().startswith(b"P6\n34 21\n65535\n")
    back, meta = lio.read(p, raw=True)
    np.testing.assert_array_equal(np.round(back * 65535).astype(np.uint16), codes)
    assert meta["bit_depth"] == 16 and meta["format"] == "ppm"
    # and through sRGB: every 16-bit code decodes and re-encodes to itself
    lin, _ = lio.read(p)
    np.testing.assert_array_equal(encode_quantise(lin, 16), codes)


@pytest.mark.parametrize("ascii", [False, True])
@pytest.mark.parametrize("bits", [8, 16])
def test_pnm_linear_round_trip(tmp_path, ascii, bits):
    img = asym(c=1)
    p = lio.write(tmp_path / "g.pgm", img, bits=bits, ascii=ascii)
    assert p.read_bytes()[:2] == (b"P2" if ascii else b"P5")
    back, meta = lio.read(p)
    codes = encode_quantise(img, bits)
    np.testing.assert_array_equal(back, decode_srgb(codes, (1 << bits) - 1))
    assert meta["display_encoded"] and meta["format"] == "pgm"


@pytest.mark.parametrize("bits", [8, 16])
def test_png_round_trip(tmp_path, bits):
    img = asym(c=4)
    back, meta = lio.read(lio.write(tmp_path / "a.png", img, bits=bits))
    q = 1 << bits
    # PNG colour is straight: the file holds sRGB(colour / alpha) (exact code round trip), alpha is linear
    # coverage quantised directly, and reading premultiplies by the stored alpha
    a = img[..., 3:]  # divided in float32, as the image is: a float64 quotient may round to the next code
    straight = np.divide(img[..., :3], a, out=np.zeros(img[..., :3].shape, np.float32), where=a > 0)
    # (the stored alpha, within half a code of the image's as asserted below, is what colour is multiplied by)
    expected = decode_srgb(encode_quantise(straight, bits), q - 1) * back[..., 3:]
    np.testing.assert_allclose(back[..., :3], expected, rtol=1e-6, atol=1e-9)  # one float32 product
    np.testing.assert_allclose(back[..., 3], img[..., 3], atol=0.5 / (q - 1) + 1e-7)
    assert meta["bit_depth"] == bits and meta["channels"] == ["R", "G", "B", "A"]


def test_jpg_within_stated_error(tmp_path):
    y, x = np.mgrid[0:64, 0:96].astype(np.float32)
    img = np.stack([x / 95, y / 63, 0.5 + 0.4 * np.sin(x / 7)], -1).astype(np.float32)  # smooth content
    enc = lambda v: colour.models.eotf_inverse_sRGB(np.clip(v, 0, 1)) * 255  # noqa: E731
    back, meta = lio.read(lio.write(tmp_path / "a.jpg", img, quality=95))
    err = np.abs(enc(back) - enc(img))
    # the stated JPG error at quality 95 (4:4:4) on smooth content, in 8-bit sRGB codes: under 8 at
    # worst and under 1 on average (measured 5.9 and 0.76; DCT quantisation, not our encoding)
    assert err.max() < 8 and err.mean() < 1.0
    assert meta["format"] == "jpg" and meta["bit_depth"] == 8
    low, _ = lio.read(lio.write(tmp_path / "b.jpg", img, quality=75))
    assert np.abs(enc(low) - enc(img)).mean() > err.mean()  # the quality option reaches the codec


def test_srgb_encoding_is_colour_science():
    x = np.linspace(-0.1, 1.1, 100001, dtype=np.float32)
    ref = np.floor(colour.models.eotf_inverse_sRGB(np.clip(x.astype(np.float64), 0, 1)) * 255 + 0.5)
    np.testing.assert_array_equal(encode_quantise(x, 8), ref)
    np.testing.assert_allclose(decode_srgb(np.arange(256), 255),
                               colour.models.eotf_sRGB(np.arange(256) / 255), rtol=1e-6)
    special = np.array([np.nan, np.inf, -np.inf, -1.0, 2.0], np.float32)
    np.testing.assert_array_equal(encode_quantise(special, 8), [0, 255, 0, 0, 255])


def test_dither_keeps_mean(tmp_path):
    img = np.full((64, 64, 1), 0.2, np.float32)  # between two 8-bit codes
    plain = encode_quantise(img, 8)
    dith = encode_quantise(img, 8, dither=True)
    target = colour.models.eotf_inverse_sRGB(0.2) * 255
    assert np.unique(plain).size == 1
    assert np.unique(dith).size > 1 and abs(dith.mean() - target) < 0.05  # TPDF noise is unbiased


def test_write_chooses_format_by_extension_or_argument(tmp_path):
    img = asym()
    assert lio.write(tmp_path / "a.jpeg", img).read_bytes()[:3] == b"\xff\xd8\xff"
    assert lio.write(tmp_path / "noext", img, format="pfm").read_bytes()[:2] == b"PF"
    with pytest.raises(lio.FormatError, match="extension"):
        lio.write(tmp_path / "a.webp", img)
    with pytest.raises(lio.FormatError, match="unknown option"):
        lio.write(tmp_path / "a.pfm", img, quality=3)


def test_atomic_write_leaves_nothing_on_failure(tmp_path):
    target = tmp_path / "x.bin"
    with pytest.raises(RuntimeError):
        with lio.atomic_write_path(target) as tmp:
            tmp.write_bytes(b"partial")
            raise RuntimeError("boom")
    assert list(tmp_path.iterdir()) == []
    target.write_bytes(b"old")
    with pytest.raises(FileExistsError):
        with lio.atomic_write_path(target, overwrite=False) as tmp:
            tmp.write_bytes(b"new")
    assert target.read_bytes() == b"old" and list(tmp_path.iterdir()) == [target]
    with lio.atomic_write_path(target, overwrite=True) as tmp:
        assert tmp.parent == tmp_path and tmp.suffix == ".bin"
        tmp.write_bytes(b"new")
    assert target.read_bytes() == b"new" and list(tmp_path.iterdir()) == [target]


def test_encoder_failure_leaves_no_file(tmp_path):
    with pytest.raises(lio.FormatError):
        lio.write(tmp_path / "a.jpg", asym(), quality=101)
    with pytest.raises(lio.FormatError):
        lio.write(tmp_path / "a.exr", asym(), compression="lzma")
    assert list(tmp_path.iterdir()) == []
