"""A photo lenslab reads as stored (an EXR, TIFF or PNG: only a JPEG's EXIF orientation and a HEIC's rotation are
applied on reading) keeps its Orientation in its copies, which hold the same stored pixels, so they are shown as the
photo is. ``Orientation`` 1 was written over it: an EXR ``oiiotool`` made of a phone's upright photo (60 x 40 stored,
Orientation 6) came out of ``lenslab convert`` shown on its side, EXR to EXR too, which kept the attribute before.

The outside values: OpenImageIO's reading of the source's and each copy's Orientation and size, exiftool's of a TIFF
photo's."""

from __future__ import annotations

import pytest

from tests.exif.exif_tools import exiftool, exiftool_write, needs_exiftool, oiio_attribute, photo, run

oiio = pytest.importorskip("OpenImageIO")
pytestmark = needs_exiftool
SHOT = ("-Make=Acme", "-Model=Upright", "-Orientation#=6", "-FocalLength=10", "-FocalLengthIn35mmFormat=28")


@pytest.mark.parametrize("ext", ["exr", "tif", "png", "jpg"])
def test_an_openimageio_exr_s_orientation_goes_with_its_copy(tmp_path, capsys, ext):
    source = photo(tmp_path / "phone.jpg", 60, 40, *SHOT)
    exr = tmp_path / "phone.exr"
    assert oiio.ImageBuf(str(source)).write(str(exr)), oiio.geterror()
    spec = oiio.ImageInput.open(str(exr)).spec()
    assert (spec.width, spec.height, oiio_attribute(exr, "Orientation")) == (60, 40, 6)  # (stored, shown turned)
    out = tmp_path / f"copy.{ext}"
    code, err = run(capsys, "convert", exr, "-o", out, "-q")
    assert code == 0, err
    spec = oiio.ImageInput.open(str(out)).spec()
    assert (spec.width, spec.height, oiio_attribute(out, "Orientation")) == (60, 40, 6)
    assert oiio_attribute(out, "Make") == "Acme"


def test_a_tiff_s_orientation_goes_with_its_copy(tmp_path, capsys):
    from lenslab.io import write
    import numpy as np

    source = tmp_path / "scan.tif"
    write(source, np.full((40, 60, 3), 0.5, np.float32), sample_type="uint8")
    exiftool_write(source, "-Make=Acme", "-Orientation#=8")
    assert exiftool(source, "Orientation", "ImageWidth")["Orientation"] == 8
    out = tmp_path / "copy.jpg"
    assert run(capsys, "convert", source, "-o", out, "-q")[0] == 0
    tags = exiftool(out, "Orientation", "ImageWidth", "ImageHeight", "Make")
    assert (tags["Orientation"], tags["ImageWidth"], tags["ImageHeight"], tags["Make"]) == (8, 60, 40, "Acme")


def test_a_jpeg_s_orientation_is_applied_and_its_copy_says_1(tmp_path, capsys):
    """A JPEG is read upright (its Orientation applied): the copy is stored upright, Orientation 1."""
    source = photo(tmp_path / "phone.jpg", 60, 40, *SHOT)
    out = tmp_path / "copy.exr"
    assert run(capsys, "convert", source, "-o", out, "-q")[0] == 0
    spec = oiio.ImageInput.open(str(out)).spec()
    assert (spec.width, spec.height, oiio_attribute(out, "Orientation")) == (40, 60, 1)
