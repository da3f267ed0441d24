"""Interop: our files read by OpenCV and the OpenEXR bindings directly, and theirs read by us.

The images are asymmetric (every pixel different), so a flipped, transposed or channel-swapped
reading fails.
"""

from __future__ import annotations

import cv2
import numpy as np
import OpenEXR
import pytest

import lenslab.io as lio
from lenslab.io.encode import decode_srgb, encode_quantise


def asym(h: int = 29, w: int = 41, c: int = 3, seed: int = 3) -> np.ndarray:
    return np.random.default_rng(seed).random((h, w, c)).astype(np.float32)


def test_orientation_marker(tmp_path):
    """One bright pixel near the top-left corner lands there in every format, through every reader."""
    img = np.zeros((10, 16, 3), np.float32)
    img[1, 2] = [1.0, 0.0, 0.0]  # red, row 1, column 2
    img[8, 13] = [0.0, 0.0, 1.0]  # blue, near the bottom-right
    for name in ("o.pfm", "o.exr", "o.ppm", "o.png", "o.jpg"):
        back, _ = lio.read(lio.write(tmp_path / name, img))
        r = np.unravel_index(np.argmax(back[..., 0]), back.shape[:2])
        b = np.unravel_index(np.argmax(back[..., 2]), back.shape[:2])
        assert (r, b) == ((1, 2), (8, 13)), name
        if name != "o.exr":
            theirs = cv2.imread(str(tmp_path / name), cv2.IMREAD_UNCHANGED)
            assert np.unravel_index(np.argmax(theirs[..., 2]), theirs.shape[:2]) == (1, 2), name  # BGR


def test_opencv_reads_our_pfm(tmp_path):
    img = asym() * 100 - 3
    lio.write(tmp_path / "a.pfm", img)
    theirs = cv2.imread(str(tmp_path / "a.pfm"), cv2.IMREAD_UNCHANGED)
    np.testing.assert_array_equal(theirs[..., ::-1], img)


@pytest.mark.parametrize("bits", [8, 16])
def test_opencv_reads_our_ppm_and_png(tmp_path, bits):
    img = asym()
    codes = encode_quantise(img, bits)
    for name in ("a.ppm", "a.png"):
        lio.write(tmp_path / name, img, bits=bits)
        theirs = cv2.imread(str(tmp_path / name), cv2.IMREAD_UNCHANGED)
        assert theirs.dtype == (np.uint8 if bits == 8 else np.uint16)
        np.testing.assert_array_equal(theirs[..., ::-1], codes)


def test_opencv_reads_our_jpg_as_we_do(tmp_path):
    lio.write(tmp_path / "a.jpg", asym(), quality=92)
    ours, _ = lio.read(tmp_path / "a.jpg", raw=True)
    theirs = cv2.imread(str(tmp_path / "a.jpg"), cv2.IMREAD_UNCHANGED)
    np.testing.assert_array_equal(np.round(ours * 255).astype(np.uint8), theirs[..., ::-1])


def test_jpg_chroma_subsampling_option(tmp_path):
    img = asym(h=32, w=32)
    sizes = {}
    for sub in ("444", "420"):
        sizes[sub] = len(lio.write(tmp_path / f"{sub}.jpg", img, quality=95, subsampling=sub).read_bytes())
    assert sizes["420"] < sizes["444"]  # half the chroma samples
    default = lio.write(tmp_path / "d.jpg", img, quality=95).read_bytes()
    assert default == (tmp_path / "444.jpg").read_bytes()  # 4:4:4 by default at quality >= 90
    default75 = lio.write(tmp_path / "d75.jpg", img, quality=75).read_bytes()
    assert default75 == lio.write(tmp_path / "s75.jpg", img, quality=75, subsampling="420").read_bytes()


@pytest.mark.parametrize("bits", [8, 16])
def test_we_read_opencv_png_and_ppm(tmp_path, bits):
    dtype = np.uint8 if bits == 8 else np.uint16
    codes = np.random.default_rng(5).integers(0, 1 << bits, (23, 31, 3)).astype(dtype)
    for name in ("c.png", "c.ppm"):
        assert cv2.imwrite(str(tmp_path / name), codes[..., ::-1].copy())
        ours, meta = lio.read(tmp_path / name)
        np.testing.assert_array_equal(ours, decode_srgb(codes, (1 << bits) - 1))
        assert meta["bit_depth"] == bits


def test_we_read_opencv_grey_and_jpg(tmp_path):
    grey = np.random.default_rng(6).integers(0, 256, (17, 19)).astype(np.uint8)
    cv2.imwrite(str(tmp_path / "g.pgm"), grey)
    cv2.imwrite(str(tmp_path / "g.png"), grey)
    for name in ("g.pgm", "g.png"):
        ours, meta = lio.read(tmp_path / name, raw=True)
        assert ours.shape == (17, 19, 1) and meta["channels"] == ["Y"]
        np.testing.assert_array_equal(np.round(ours[..., 0] * 255), grey)
    rgb = (asym() * 255).astype(np.uint8)
    cv2.imwrite(str(tmp_path / "c.jpg"), rgb[..., ::-1].copy())
    ours, _ = lio.read(tmp_path / "c.jpg", raw=True)
    np.testing.assert_array_equal(np.round(ours * 255).astype(np.uint8),
                                  cv2.imread(str(tmp_path / "c.jpg"))[..., ::-1])


def test_we_read_opencv_pfm(tmp_path):
    img = asym() * 7
    cv2.imwrite(str(tmp_path / "c.pfm"), img[..., ::-1].copy())
    ours, _ = lio.read(tmp_path / "c.pfm")
    np.testing.assert_array_equal(ours, img)


@pytest.mark.parametrize("pixel_type", ["half", "float"])
def test_openexr_reads_our_exr(tmp_path, pixel_type):
    img = asym(c=4) * 10
    lio.write(tmp_path / "a.exr", img, pixel_type=pixel_type)
    f = OpenEXR.File(str(tmp_path / "a.exr"), separate_channels=True)
    chans = f.channels()
    assert sorted(chans) == ["A", "B", "G", "R"]
    dtype = np.float16 if pixel_type == "half" else np.float32
    for i, name in enumerate("RGBA"):
        assert chans[name].pixels.dtype == dtype
        np.testing.assert_array_equal(chans[name].pixels, img[..., i].astype(dtype))
    assert f.header()["compression"] == OpenEXR.ZIP_COMPRESSION


def test_we_read_openexr_written_files(tmp_path):
    img = asym(c=3)
    header = {"compression": OpenEXR.PIZ_COMPRESSION, "type": OpenEXR.scanlineimage, "comments": "hello"}
    chans = {c: img[..., i].astype(np.float16) for i, c in enumerate("RGB")}
    chans["left.R"] = img[..., 2].astype(np.float32)
    chans["left.G"] = img[..., 0].astype(np.float32)
    chans["left.B"] = img[..., 1].astype(np.float32)
    OpenEXR.File(header, chans).write(str(tmp_path / "t.exr"))
    base, meta = lio.read(tmp_path / "t.exr")
    np.testing.assert_array_equal(base, img.astype(np.float16).astype(np.float32))
    assert meta["attributes"]["comments"] == "hello" and meta["sample_type"] == "half"
    left, meta = lio.read(f"{tmp_path / 't.exr'}:left")
    np.testing.assert_array_equal(left, img[..., [2, 0, 1]])
    assert meta["layer"] == "left" and meta["sample_type"] == "float"
