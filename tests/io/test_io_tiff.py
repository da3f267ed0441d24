"""TIFF: every sample type and channel count, checked against tifffile directly and colour-science's sRGB."""

from __future__ import annotations

import colour
import numpy as np
import pytest
import tifffile

import lenslab.io as lio

SAMPLE = {"float": np.float32, "half": np.float16, "uint16": np.uint16, "uint8": np.uint8}


def _image(c, seed=0):
    rng = np.random.default_rng(seed)
    img = rng.random((6, 9, c)).astype(np.float32)
    img[0, 0, :] = 0.0
    img[-1, -1, :] = 1.0
    return img


def _srgb_codes(x, bits):
    """colour-science's sRGB encoding, rounded to the nearest code (the reference for integer TIFFs)."""
    return np.round(colour.cctf_encoding(np.clip(x.astype(np.float64), 0, 1), "sRGB") * (2**bits - 1))


@pytest.mark.parametrize("sample_type", list(SAMPLE))
@pytest.mark.parametrize("c", [1, 2, 3, 4])
def test_what_tifffile_reads_of_ours(tmp_path, sample_type, c):
    img = _image(c)
    path = tmp_path / "a.tif"
    lio.write(path, img, sample_type=sample_type)
    with tifffile.TiffFile(path) as tif:
        page = tif.pages.first
        stored = page.asarray()
        assert page.photometric.name == ("RGB" if c >= 3 else "MINISBLACK")
        assert len(page.extrasamples) == (1 if c in (2, 4) else 0)
        extra = [int(v) for v in page.extrasamples]
    assert stored.dtype == SAMPLE[sample_type]
    stored = stored.reshape(6, 9, c)
    if sample_type in ("float", "half"):
        np.testing.assert_array_equal(stored, img.astype(SAMPLE[sample_type]))  # exact: a plain cast
    else:
        bits = 16 if sample_type == "uint16" else 8
        colour_ch = c - 1 if c in (2, 4) else c
        straight = img[..., :colour_ch].astype(np.float64)
        if c in (2, 4):  # integer TIFF alpha is unassociated (ExtraSamples 2): straight colour, a / alpha
            a = img[..., -1:].astype(np.float64)
            straight = np.divide(straight, a, out=np.zeros_like(straight), where=a > 0)
            assert extra == [2]
        np.testing.assert_array_equal(stored[..., :colour_ch], _srgb_codes(straight, bits))
        if c in (2, 4):  # alpha is linear coverage: value * maxval rounded
            np.testing.assert_array_equal(stored[..., -1], np.round(img[..., -1].astype(np.float64) * (2**bits - 1)))
    back, meta = lio.read(path)
    assert back.shape == img.shape and meta["format"] == "tiff"
    assert meta["display_encoded"] == (sample_type.startswith("uint"))


@pytest.mark.parametrize("dtype", [np.float32, np.float16, np.float64, np.uint16, np.uint8])
@pytest.mark.parametrize("planar", [False, True])
def test_what_we_read_of_tifffiles(tmp_path, dtype, planar):
    rng = np.random.default_rng(1)
    if np.dtype(dtype).kind == "f":
        data = (rng.random((5, 8, 3)) * 40).astype(dtype)
    else:
        data = rng.integers(0, np.iinfo(dtype).max, (5, 8, 3), endpoint=True).astype(dtype)
    path = tmp_path / "t.tiff"
    if planar:
        tifffile.imwrite(path, np.moveaxis(data, -1, 0), photometric="rgb", planarconfig="separate")
    else:
        tifffile.imwrite(path, data, photometric="rgb", compression="zlib")
    image, meta = lio.read(path)
    assert image.shape == (5, 8, 3) and image.dtype == np.float32
    if np.dtype(dtype).kind == "f":
        np.testing.assert_array_equal(image, data.astype(np.float32))
        assert not meta["display_encoded"]
    else:
        maxval = np.iinfo(dtype).max
        expected = colour.cctf_decoding(data / maxval, "sRGB")
        # float32 table of the float64 EOTF: one float32 rounding
        np.testing.assert_allclose(image, expected, rtol=2e-7, atol=1e-9)
        raw, _ = lio.read(path, raw=True)
        np.testing.assert_allclose(raw, data / maxval, rtol=2e-7)  # float32 division


def test_alpha_and_grey_from_tifffile(tmp_path):
    rgba = np.arange(4 * 5 * 4, dtype=np.uint8).reshape(4, 5, 4) * 3
    tifffile.imwrite(tmp_path / "a.tif", rgba, photometric="rgb", extrasamples=["unassalpha"])
    image, meta = lio.read(tmp_path / "a.tif")
    assert meta["channels"] == ["R", "G", "B", "A"]
    np.testing.assert_allclose(image[..., 3], rgba[..., 3] / 255.0, rtol=2e-7)  # alpha stays linear
    grey = np.linspace(0, 7, 12, dtype=np.float32).reshape(3, 4)
    tifffile.imwrite(tmp_path / "g.tif", grey)
    image, meta = lio.read(tmp_path / "g.tif")
    assert meta["channels"] == ["Y"]
    np.testing.assert_array_equal(image[..., 0], grey)


def test_multipage_reads_the_first_and_counts(tmp_path):
    with tifffile.TiffWriter(tmp_path / "m.tif") as w:
        w.write(np.full((3, 4), 2.0, np.float32))
        w.write(np.full((3, 4), 5.0, np.float32))
    image, meta = lio.read(tmp_path / "m.tif")
    assert (image == 2.0).all() and meta["attributes"]["pages"] == 2


def test_detected_by_content_and_refusals(tmp_path):
    data = np.ones((2, 3, 3), np.float32)
    tifffile.imwrite(tmp_path / "named.dat", data, photometric="rgb")
    assert lio.read(tmp_path / "named.dat")[0].shape == (2, 3, 3)  # magic bytes, never the name
    tifffile.imwrite(tmp_path / "p.tif", np.zeros((2, 3), np.uint8), photometric="palette",
                     colormap=np.zeros((3, 256), np.uint16))
    with pytest.raises(lio.FormatError, match="PALETTE"):
        lio.read(tmp_path / "p.tif")
    with pytest.raises(lio.FormatError, match="sample_type"):
        lio.write(tmp_path / "x.tif", data, sample_type="int32")
    (tmp_path / "bad.tif").write_bytes(b"II*\x00" + b"\xff" * 12)
    with pytest.raises(lio.FormatError):
        lio.read(tmp_path / "bad.tif")
