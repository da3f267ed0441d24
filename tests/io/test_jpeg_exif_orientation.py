"""A JPEG whose EXIF ``Orientation`` says how to show it (a phone photo held upright is stored on its side, tag 6)
reads as shown: as OpenCV's ``imread`` with ``IMREAD_COLOR`` (which applies the tag) decodes it, code for code, and
in the size Pillow's ``ImageOps.exif_transpose`` gives. Both are outside lenslab; the files are written by Pillow
with the tag set, so every one of the eight values is checked."""

from __future__ import annotations

import cv2
import numpy as np
import pytest
from PIL import Image, ImageOps

import lenslab
from lenslab.cli.main import main


def _photo(path, orientation: int) -> None:
    """A 48 x 64 JPEG of 8-pixel blocks (every turn and mirror tells apart) with the tag set to ``orientation``."""
    blocks = np.random.default_rng(7).integers(0, 256, (6, 8, 3))
    codes = np.kron(blocks, np.ones((8, 8, 1))).astype(np.uint8)
    exif = Image.Exif()
    exif[0x0112] = orientation
    Image.fromarray(codes).save(path, quality=95, exif=exif.tobytes())


@pytest.mark.parametrize("orientation", range(1, 9))
def test_read_as_opencv_and_pillow_show_it(tmp_path, orientation):
    path = tmp_path / f"o{orientation}.jpg"
    _photo(path, orientation)
    shown = cv2.imread(str(path), cv2.IMREAD_COLOR)[..., ::-1]  # OpenCV applies the tag; RGB order
    with Image.open(path) as im:
        upright = ImageOps.exif_transpose(im)
        size = upright.size  # (width, height)
    image, meta = lenslab.read(path, raw=True)  # raw: code / 255, so the decoders' codes compare exactly
    assert (image.shape[1], image.shape[0]) == size
    np.testing.assert_array_equal(np.rint(image * 255).astype(np.uint8), shown)
    assert ("orientation" in meta["attributes"]) == (orientation != 1)


def test_info_says_the_photo_was_turned(tmp_path, capsys):
    path = tmp_path / "portrait.jpg"
    _photo(path, 6)
    assert main(["info", str(path)]) == 0
    out = capsys.readouterr().out
    assert "JPG 48 x 64" in out  # shown upright: 48 wide, 64 tall
    assert "EXIF orientation 6" in out and "turned 90 degrees clockwise" in out


@pytest.mark.parametrize("cut", [10, 14, 20, 28])  # 28: its first IFD entry two bytes short
def test_a_damaged_exif_segment_reads_as_stored(tmp_path, cut):
    """An Exif segment cut short (its IFD beyond the segment) is no orientation: the image as stored, as OpenCV's
    IMREAD_UNCHANGED decodes it."""
    path = tmp_path / "cut.jpg"
    _photo(path, 6)
    data = bytearray(path.read_bytes())
    at = data.find(b"Exif\x00\x00") - 4  # the APP1 marker
    length = int.from_bytes(data[at + 2:at + 4], "big")
    data[at + 2:at + 4] = cut.to_bytes(2, "big")  # the segment now ends inside its TIFF header or IFD
    data[at + 2 + cut:at + 2 + length] = b""
    path.write_bytes(bytes(data))
    stored = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)[..., ::-1]
    image, _ = lenslab.read(path, raw=True)
    np.testing.assert_array_equal(np.rint(image * 255).astype(np.uint8), stored)
