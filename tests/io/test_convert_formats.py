"""convert with the new formats: EXR keeps its pixel type, folders mirrored, '**' recursion, TIFF and .hdr."""

from __future__ import annotations

import cv2
import numpy as np
import OpenEXR
import pytest
import tifffile

import lenslab.io as lio
from lenslab.cli.main import main


def _img(seed=0):
    return (np.random.default_rng(seed).random((8, 16, 3)) * 4).astype(np.float32)


def _exr_type(path) -> str:
    """The pixel type OpenEXR itself reports for the R channel."""
    ch = OpenEXR.File(str(path), separate_channels=True).channels()["R"]
    return {np.dtype(np.float16): "half", np.dtype(np.float32): "float"}[ch.pixels.dtype]


def test_exr_to_exr_keeps_the_inputs_pixel_type(tmp_path):
    lio.write(tmp_path / "f.exr", _img(), pixel_type="float")
    lio.write(tmp_path / "h.exr", _img(), pixel_type="half")
    assert main(["convert", str(tmp_path / "f.exr"), str(tmp_path / "h.exr"), "--to", "exr", "-o",
                 str(tmp_path / "out"), "-q"]) == 0
    assert _exr_type(tmp_path / "out" / "f.exr") == "float"
    assert _exr_type(tmp_path / "out" / "h.exr") == "half"
    assert main(["convert", str(tmp_path / "f.exr"), "--to", "exr", "-o", str(tmp_path / "o2"),
                 "--pixel-type", "half", "-q"]) == 0
    assert _exr_type(tmp_path / "o2" / "f.exr") == "half"
    np.testing.assert_array_equal(lio.read(tmp_path / "out" / "f.exr")[0], _img())  # float kept bit for bit


@pytest.fixture
def tree(tmp_path):
    for rel in ("a.exr", "d1/b.exr", "d1/d2/c.exr", "d1/d2/notes.txt"):
        p = tmp_path / "in" / rel
        p.parent.mkdir(parents=True, exist_ok=True)
        if rel.endswith(".exr"):
            lio.write(p, _img())
        else:
            p.write_text("not an image")
    return tmp_path


def test_recursive_mirrors_the_tree(tree):
    assert main(["convert", str(tree / "in"), "--recursive", "--to", "hdr", "-o", str(tree / "out"), "-q"]) == 0
    found = sorted(p.relative_to(tree / "out").as_posix() for p in (tree / "out").rglob("*") if p.is_file())
    assert found == ["a.hdr", "d1/b.hdr", "d1/d2/c.hdr"]
    # without --recursive a folder is one level deep, as before
    assert main(["convert", str(tree / "in"), "--to", "hdr", "-o", str(tree / "flat"), "-q"]) == 0
    assert sorted(p.name for p in (tree / "flat").rglob("*") if p.is_file()) == ["a.hdr"]
    # OpenCV reads what was written
    assert cv2.imread(str(tree / "out" / "d1" / "d2" / "c.hdr"), cv2.IMREAD_UNCHANGED).shape == (8, 16, 3)


def test_double_star_glob_recurses(tree):
    assert main(["convert", str(tree / "in" / "**" / "*.exr"), "--to", "tiff", "-o", str(tree / "out"), "-q"]) == 0
    found = sorted(p.relative_to(tree / "out").as_posix() for p in (tree / "out").rglob("*") if p.is_file())
    assert found == ["a.tif", "d1/b.tif", "d1/d2/c.tif"]
    stored = tifffile.imread(tree / "out" / "d1" / "b.tif")
    assert stored.dtype == np.float32  # HDR to TIFF stays float, no tone curve
    np.testing.assert_array_equal(stored, lio.read(tree / "in" / "d1" / "b.exr")[0])


def test_tiff_bits_give_display_encoded_integers(tmp_path):
    lio.write(tmp_path / "f.exr", _img(), pixel_type="float")
    assert main(["convert", str(tmp_path / "f.exr"), "--to", "tiff", "--bits", "16", "-o",
                 str(tmp_path / "o.tif"), "--tone", "clamp", "-q"]) == 0
    stored = tifffile.imread(tmp_path / "o.tif")
    assert stored.dtype == np.uint16
    import colour

    # clamp tone curve then colour-science's sRGB encoding, rounded to 16-bit codes
    expected = np.round(colour.cctf_encoding(np.clip(_img().astype(np.float64), 0, 1), "sRGB") * 65535)
    np.testing.assert_array_equal(stored, expected)
