"""An EXR OpenImageIO writes of a photo holds its rationals (FocalLength, ExposureTime, FNumber, SubjectDistance) as
32-bit floats: ``lenslab convert`` of it writes the photo's own rationals (681/100, not 14281605/2097152, which
exiftool showed as 6.809999943 mm), as OpenImageIO's own conversion of that EXR does, and ``--from exif`` on it gives
the photo's field of view. (OpenImageIO's own conversion finds three of the four: its SubjectDistance is 13.387999.)

The outside values: exiftool's readings of the photo, of OpenImageIO's JPEG of the EXR and of lenslab's outputs
(``-n``: the rational's quotient), tifffile's rational terms, and exiftool's FOV of the photo."""

from __future__ import annotations

import math

import pytest

from tests.exif.exif_tools import exiftool, from_exif_fov, needs_exiftool, photo, run

oiio = pytest.importorskip("OpenImageIO")
pytestmark = needs_exiftool
SHOT = ("-Make=Acme", "-Model=Float One", "-FocalLength=6.81", "-ExposureTime=1/250", "-FNumber=1.85",
        "-SubjectDistance=13.388", "-FocalPlaneXResolution=100", "-FocalPlaneYResolution=100",
        "-FocalPlaneResolutionUnit#=3", "-ExifImageWidth=64", "-ExifImageHeight=48")
NUMBERS = ("FocalLength", "ExposureTime", "FNumber", "SubjectDistance")


def oiio_exr(tmp_path):
    source = photo(tmp_path / "p.jpg", 64, 48, *SHOT)
    exr = tmp_path / "oiio.exr"
    buf = oiio.ImageBuf(str(source))
    assert buf.write(str(exr)), oiio.geterror()
    types = {a.name: str(a.type) for a in oiio.ImageInput.open(str(exr)).spec().extra_attribs}
    assert types["Exif:FocalLength"] == types["ExposureTime"] == "float"  # (OpenImageIO writes 32-bit floats)
    return source, exr


@pytest.mark.parametrize("ext", ["jpg", "png", "tif"])
def test_an_openimageio_exr_s_float_rationals_are_the_photo_s(tmp_path, capsys, ext):
    source, exr = oiio_exr(tmp_path)
    original = exiftool(source, *NUMBERS)
    assert [original[n] for n in NUMBERS] == [6.81, 0.004, 1.85, 13.388]
    theirs = tmp_path / "oiio.jpg"
    assert oiio.ImageBuf(str(exr)).write(str(theirs), "uint8"), oiio.geterror()
    theirs = exiftool(theirs, *NUMBERS)  # (OpenImageIO's SubjectDistance: 13387999/1000000)
    assert [theirs[n] for n in NUMBERS[:3]] == [original[n] for n in NUMBERS[:3]]
    out = tmp_path / f"lenslab.{ext}"
    code, err = run(capsys, "convert", exr, "-o", out, "-q")
    assert code == 0, err
    assert exiftool(out, *NUMBERS) == {**original, "SourceFile": str(out)}


def test_a_tiff_of_an_openimageio_exr_holds_the_photo_s_rational_terms(tmp_path, capsys):
    tifffile = pytest.importorskip("tifffile")
    source, exr = oiio_exr(tmp_path)
    out = tmp_path / "lenslab.tif"
    assert run(capsys, "convert", exr, "-o", out, "-q")[0] == 0
    with tifffile.TiffFile(out) as tif:
        exif = tif.pages[0].tags["ExifTag"].value
    assert (exif["FocalLength"], exif["ExposureTime"], exif["FNumber"]) == ((681, 100), (1, 250), (37, 20))


def test_from_exif_on_an_openimageio_exr_gives_the_photo_s_field(tmp_path, capsys):
    """No 35 mm equivalent: the field comes from FocalLength and the focal plane (100 pixels a centimetre: a 6.4 x 4.8
    mm sensor), so a float's 6.8099999 mm moved it by 4e-7 degree (lenslab's note gives 12 significant digits: 1e-10
    degree here)."""
    source, exr = oiio_exr(tmp_path)
    sensor_width = 64 / 100 * 10.0  # mm: 64 pixels at 100 a centimetre
    expected = math.degrees(2 * math.atan(sensor_width / (2 * 6.81)))  # (the photo's 6.81 mm, in float64)
    assert from_exif_fov(capsys, exr, tmp_path) == pytest.approx(expected, abs=1e-9)


def test_openimageio_carries_lenslab_s_exr_rationals_on_to_a_jpeg(tmp_path, capsys):
    """lenslab's EXR of a photo holds its rationals as OpenImageIO's floats: OpenImageIO's JPEG writer drops an
    ``Exif:FocalLength`` held as a double, so ``oiiotool lenslab.exr -o copy.jpg`` lost the focal length, exposure
    and f-number; it keeps them now, and lenslab reads the EXR's rationals back as the photo's."""
    source = photo(tmp_path / "p.jpg", 64, 48, *SHOT)
    exr = tmp_path / "lenslab.exr"
    assert run(capsys, "convert", source, "-o", exr, "-q")[0] == 0
    types = {a.name: str(a.type) for a in oiio.ImageInput.open(str(exr)).spec().extra_attribs}
    assert types["Exif:FocalLength"] == types["ExposureTime"] == types["FNumber"] == "float"
    theirs = tmp_path / "oiio.jpg"
    assert oiio.ImageBuf(str(exr)).write(str(theirs), "uint8"), oiio.geterror()
    original, copied = exiftool(source, *NUMBERS[:3]), exiftool(theirs, *NUMBERS[:3])
    assert [copied[n] for n in NUMBERS[:3]] == [original[n] for n in NUMBERS[:3]] == [6.81, 0.004, 1.85]
    back = tmp_path / "back.tif"
    assert run(capsys, "convert", exr, "-o", back, "-q")[0] == 0
    assert exiftool(back, *NUMBERS) == {**exiftool(source, *NUMBERS), "SourceFile": str(back)}
