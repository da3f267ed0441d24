"""The input budget's header readers against the libraries that read the same files (tifffile, OpenCV,
OpenEXR), the Radiance decoder against OpenCV's, the NaN/inf counts of the writers, and the note of a
view that sees nothing of its source."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import lenslab.io as lio
from lenslab.io.registry import formats


@pytest.fixture
def image():
    return np.random.default_rng(3).random((37, 53, 3), dtype=np.float32) * 3


def test_tiff_declaration_matches_tifffile(tmp_path, image):
    import tifffile

    from lenslab.io.tiff.layout import declare_tiff

    path = tmp_path / "a.tif"
    tifffile.imwrite(path, image, compression="zlib", rowsperstrip=8, photometric="rgb")
    d = declare_tiff(path)
    with tifffile.TiffFile(path) as tif:
        page = tif.pages.first
        assert (d.width, d.height, d.channels) == (page.imagewidth, page.imagelength, page.samplesperpixel)
        assert d.held == sum(page.databytecounts)
    assert d.min_bytes <= d.held


@pytest.mark.parametrize("ext", [".jpg", ".png"])
def test_jpeg_and_png_declarations_match_opencv(tmp_path, image, ext):
    import cv2

    path = tmp_path / f"a{ext}"
    lio.write(path, image)
    d = formats()[ext[1:]].declare(path)
    decoded = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    assert (d.height, d.width) == decoded.shape[:2]
    assert d.min_bytes <= d.held


def test_exr_declaration_matches_openexr(tmp_path, image):
    import OpenEXR

    path = tmp_path / "a.exr"
    lio.write(path, image)
    d = formats()["exr"].declare(path)
    (x0, y0), (x1, y1) = OpenEXR.File(str(path), header_only=True).parts[0].header["displayWindow"]
    assert (d.width, d.height) == (x1 - x0 + 1, y1 - y0 + 1)


def test_radiance_decoding_is_opencv_plus_half_a_mantissa_step(tmp_path, image):
    """OpenCV (Ward's rgbe.c) decodes m * 2**(e - 136); Radiance's colr_color, which lenslab follows,
    (m + 0.5) * 2**(e - 136): the difference is exactly half a step of each pixel's exponent."""
    import cv2

    path = tmp_path / "a.hdr"
    lio.write(path, image, rle=False)
    ours, _ = lio.read(path)
    theirs = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)[..., ::-1].astype(np.float64)
    raw = np.frombuffer(path.read_bytes()[-(37 * 53 * 4):], np.uint8)  # flat pixels
    e = raw.reshape(37, 53, 4)[..., 3].astype(np.float64)
    step = np.where(e > 0, np.ldexp(1.0, (e - 136).astype(int)), 0.0)[..., None]
    np.testing.assert_array_equal(ours.astype(np.float64) - theirs, np.broadcast_to(0.5 * step, ours.shape))


@pytest.mark.parametrize("ext", [".hdr", ".png", ".ppm"])
def test_writers_count_what_they_replace(tmp_path, image, ext):
    from lenslab.io.encode import NonFiniteWarning

    image[0, 0, 0] = image[1, 2, 1] = image[3, 3, 2] = np.nan
    image[4, 4, 0] = image[5, 5, 1] = np.inf
    image[6, 6, 0] = -np.inf
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        lio.write(tmp_path / f"a{ext}", image)
    notes = [str(w.message) for w in caught if issubclass(w.category, NonFiniteWarning)]
    assert len(notes) == 1 and "3 NaN, 2 +inf, 1 -inf" in notes[0], notes


def test_a_view_that_sees_nothing_of_its_source_says_so():
    from lenslab.lenses import Camera
    from lenslab.warp import warp
    from lenslab.warp.engine import EmptyViewWarning

    src = Camera.from_spec("perspective:fov=30", (32, 32))
    behind = Camera.from_spec("perspective:fov=60", (16, 16), yaw=180)  # every ray has z < 0
    with pytest.warns(EmptyViewWarning, match="0% coverage"):
        _, alpha = warp(np.ones((32, 32, 3), np.float32), src, behind)
    assert not alpha.any()


@pytest.mark.parametrize("data", [
    b"Pf\n" + b"7" * 200 + b" 1\n-1\n" + bytes(64),  # found by the PFM fuzz target: the whole token was quoted
    b"#?RADIANCE\nEXPOSURE=" + b"x" * 5000 + b"\n\n-Y 1 +X 1\n" + bytes(4),
])
def test_messages_quote_a_few_dozen_characters_of_a_file(tmp_path, data):
    path = tmp_path / "f.img"
    path.write_bytes(data)
    with pytest.raises(lio.FormatError) as info:
        lio.read(path)
    assert len(str(info.value)) < len(str(path)) + 200 and "\n" not in str(info.value)


def test_kalibr_values_are_cut_in_messages(tmp_path):
    from lenslab.calibfiles import CameraFileError, read_lens

    path = tmp_path / "camchain.yaml"
    path.write_text("cam0:\n  camera_model: " + "z" * 10000 + "\n  intrinsics: [1, 1, 1, 1]\n  distortion_model: none\n"
                    "  distortion_coeffs: []\n  resolution: [64, 64]\n")
    with pytest.raises(CameraFileError) as info:
        read_lens(str(path))
    assert "camera_model" in str(info.value) and len(str(info.value)) < len(str(path)) + 200
