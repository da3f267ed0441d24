"""``lenslab convert`` carries a photo's camera EXIF into JPEG (APP1), TIFF (Exif IFD), PNG (eXIf) and EXR
(OpenImageIO's attribute names), so ``lenslab warp converted.exr --from exif`` sees the photo's lens: exiftool reads
each output's Model, FocalLengthIn35mmFilm and Orientation (OpenImageIO an EXR's) as the values of the source's
that still hold, and ``--from exif`` on each output gives the field of view exiftool gives the original, to 1e-9
degree (exiftool prints 15 digits; lenslab's note 12 significant ones, 1e-10 degree here). GPS, the thumbnail and
maker notes of the source are not carried."""

from __future__ import annotations

import pytest

from tests.exif.exif_tools import OUTPUTS, exiftool, from_exif_fov, needs_exiftool, photo, recorded_frame, run, \
    shown_fov, tags_of_output

pytestmark = needs_exiftool
PIXEL_PHOTO = ("formats", "oiio-images", "ultrahdr_sky.jpg")  # in ../shared/data: a Pixel 6 Pro's Ultra HDR photo


def no_private_tags(out) -> None:
    if str(out).endswith(".exr"):
        from OpenImageIO import ImageInput

        spec = ImageInput.open(str(out)).spec()
        assert not [a.name for a in spec.extra_attribs if a.name.startswith("GPS")]
        return
    found = exiftool(out, "GPS:all", "ThumbnailImage", "MakerNote")
    assert not [k for k in found if k.startswith("GPS") or k in ("ThumbnailImage", "MakerNote")], found


@pytest.mark.shared_data
@pytest.mark.parametrize("ext", OUTPUTS)
def test_a_phone_photo_keeps_its_camera_in_every_format(shared_data, tmp_path, capsys, ext):
    source = shared_data.joinpath(*PIXEL_PHOTO)
    original = exiftool(source, "Model", "FocalLengthIn35mmFormat", "FOV", "GPSLatitudeRef")
    assert original["GPSLatitudeRef"]  # (the photo records where it was taken)
    out = tmp_path / f"sky.{ext}"
    code, err = run(capsys, "convert", source, "-o", out, "-q")
    assert code == 0, err
    tags = tags_of_output(out)
    assert tags["Model"] == original["Model"] == "Pixel 6 Pro"
    assert tags["FocalLengthIn35mmFormat"] == original["FocalLengthIn35mmFormat"] == 24
    assert tags["Orientation"] == 1
    assert recorded_frame(tags, out) == (4080, 3072)
    no_private_tags(out)
    assert from_exif_fov(capsys, out, tmp_path) == pytest.approx(shown_fov(original, 4080, 3072), abs=1e-9)


TURNED_SHOT = ("-Make=Acme", "-Model=Turned One", "-Orientation#=6", "-FocalLength=6.81",
               "-DateTimeOriginal=2024:05:06 07:08:09", "-ExposureTime=0.01", "-FNumber=1.8", "-ISO=100",
               "-GPSLatitude=48.1", "-GPSLatitudeRef=N", "-GPSLongitude=11.5", "-GPSLongitudeRef=E")


@pytest.mark.parametrize("ext", OUTPUTS)
def test_a_turned_photo_is_written_upright_with_its_35mm_equivalent(tmp_path, capsys, ext):
    """Stored 60 x 40 with Orientation 6 (a phone held upright): shown, and written, 40 x 60; the output says
    Orientation 1 and its own frame, and keeps the 35 mm equivalent (a field across the whole frame)."""
    source = photo(tmp_path / "turned.jpg", 60, 40, *TURNED_SHOT, "-FocalLengthIn35mmFormat=26")
    original = exiftool(source, "Model", "FocalLengthIn35mmFormat", "FOV", "Orientation")
    assert original["Orientation"] == 6
    out = tmp_path / f"upright.{ext}"
    code, err = run(capsys, "convert", source, "-o", out, "-q")
    assert code == 0, err
    tags = tags_of_output(out)
    assert (tags["Model"], tags["FocalLengthIn35mmFormat"], tags["Orientation"]) == ("Turned One", 26, 1)
    assert recorded_frame(tags, out) == (40, 60)
    no_private_tags(out)
    assert from_exif_fov(capsys, out, tmp_path) == pytest.approx(shown_fov(original, 40, 60), abs=1e-9)


@pytest.mark.parametrize("ext", OUTPUTS)
def test_a_turned_photos_focal_plane_turns_with_it(tmp_path, capsys, ext):
    """Without FocalLengthIn35mmFilm, the field comes from FocalLength on the sensor the focal plane's resolution
    gives (80 and 70 pixels per cm across the stored 60 x 40 frame: 7.5 x 5.714 mm): written upright, X and Y
    change places, so the output's sensor is the same one turned and its field exiftool's of the original."""
    source = photo(tmp_path / "plane.jpg", 60, 40, *TURNED_SHOT, "-FocalPlaneResolutionUnit=cm",
                   "-FocalPlaneXResolution=80", "-FocalPlaneYResolution=70")
    original = exiftool(source, "FOV", "FocalPlaneXResolution", "FocalPlaneYResolution", "FocalLengthIn35mmFormat")
    assert "FocalLengthIn35mmFormat" not in original
    out = tmp_path / f"upright.{ext}"
    code, err = run(capsys, "convert", source, "-o", out, "-q")
    assert code == 0, err
    tags = tags_of_output(out)
    assert (tags["FocalPlaneXResolution"], tags["FocalPlaneYResolution"]) == (70, 80)
    assert from_exif_fov(capsys, out, tmp_path) == pytest.approx(shown_fov(original, 40, 60), abs=1e-9)


@pytest.mark.parametrize("ext", ("png", "exr"))
def test_tonemap_keeps_the_camera_too(tmp_path, capsys, ext):
    source = photo(tmp_path / "turned.jpg", 60, 40, *TURNED_SHOT, "-FocalLengthIn35mmFormat=26")
    original = exiftool(source, "FOV")
    out = tmp_path / f"toned.{ext}"
    code, err = run(capsys, "tonemap", source, "-o", out, "-q", "--curve", "clamp")
    assert code == 0, err
    tags = tags_of_output(out)
    assert (tags["Model"], tags["FocalLengthIn35mmFormat"], tags["Orientation"]) == ("Turned One", 26, 1)
    no_private_tags(out)
    assert from_exif_fov(capsys, out, tmp_path) == pytest.approx(shown_fov(original, 40, 60), abs=1e-9)


def test_a_heic_photos_camera_reaches_a_jpeg(tmp_path, capsys):
    """A HEIC (pillow-heif's encoder, its EXIF from Pillow) converted to JPEG: exiftool reads the same camera and
    35 mm equivalent in both, and --from exif on the JPEG gives exiftool's field of the HEIC."""
    pillow_heif = pytest.importorskip("pillow_heif")
    import numpy as np
    from PIL import Image
    from PIL.TiffImagePlugin import IFDRational

    exif = Image.Exif()
    exif[0x010F], exif[0x0110] = "Acme", "Heic Three"
    exif.get_ifd(0x8769)[0xA405], exif.get_ifd(0x8769)[0x920A] = 26, IFDRational(681, 100)
    pillow_heif.from_pillow(Image.fromarray(np.full((48, 64, 3), 120, np.uint8))).save(
        tmp_path / "p.heic", exif=exif.tobytes(), quality=90)
    original = exiftool(tmp_path / "p.heic", "Model", "FocalLengthIn35mmFormat", "FOV")
    code, err = run(capsys, "convert", tmp_path / "p.heic", "-o", tmp_path / "p.jpg", "-q")
    assert code == 0, err
    tags = tags_of_output(tmp_path / "p.jpg")
    assert (tags["Model"], tags["FocalLengthIn35mmFormat"]) == (original["Model"], original["FocalLengthIn35mmFormat"])
    assert recorded_frame(tags, tmp_path / "p.jpg") == (64, 48)
    assert from_exif_fov(capsys, tmp_path / "p.jpg", tmp_path) == pytest.approx(shown_fov(original, 64, 48), abs=1e-9)


@pytest.mark.parametrize("ext, options", [("jpg", ()), ("jpg", ("--display", "Display P3")), ("png", ()),
                                          ("tif", ()), ("tif", ("--bits", "16"))])
def test_exiftool_finds_every_tag_exif_requires(tmp_path, capsys, ext, options):
    """exiftool's -validate: no required tag missing, none where Exif forbids it (PixelXDimension in a TIFF), and a
    ColorSpace that says what the samples are (1 sRGB; 0xFFFF uncalibrated: Display P3's profile, a TIFF's linear
    floats). Its one other warning, a TIFF's compression 8 (Adobe Deflate, tifffile's zlib), is no EXIF's."""
    import subprocess

    from tests.exif.exif_tools import EXIFTOOL

    source = photo(tmp_path / "turned.jpg", 60, 40, *TURNED_SHOT, "-FocalLengthIn35mmFormat=26")
    out = tmp_path / f"copy.{ext}"
    code, err = run(capsys, "convert", source, "-o", out, "-q", *options)
    assert code == 0, err
    said = subprocess.run([EXIFTOOL, "-validate", "-warning", "-a", "-s", str(out)], capture_output=True, text=True,
                          check=True, timeout=60).stdout
    warnings = [w for w in said.splitlines() if w.startswith("Warning") and "0x0103 Compression" not in w]
    assert warnings == [], said
    assert exiftool(out, "Model").get("Model") == "Turned One"  # (the block is there to be validated)
    srgb = not options and ext != "tif" or options == ("--bits", "16")
    assert exiftool(out, "ColorSpace").get("ColorSpace") == (None if ext == "png" else 1 if srgb else 0xFFFF)
