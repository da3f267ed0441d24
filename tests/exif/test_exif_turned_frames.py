"""A photo whose pixels stand turned a quarter from the frame its EXIF records (PixelXDimension x PixelYDimension 60 x
40 over 40 x 60 pixels: a JPEG turned losslessly with its Orientation reset to 1, as jpegtran and photo tools do, or a
HEIC whose irot libheif applies) gives its copies a focal plane turned with it: X and Y change places. They were
scaled instead, as for a resize, so a portrait copy recorded a landscape sensor (0.06 x 0.02 inch under 40 x 60
pixels); ``--from exif`` on the photo already took it as turned.

The outside values: exiftool's readings of the photo's and the copy's frame and focal plane (the sensor each records:
PixelXDimension / FocalPlaneXResolution across, PixelYDimension / FocalPlaneYResolution down)."""

from __future__ import annotations

import numpy as np
import pytest

from tests.exif.exif_tools import exiftool, needs_exiftool, photo, run

pytestmark = needs_exiftool
PLANE = ("-Make=Acme", "-FocalLength=10", "-FocalPlaneXResolution=1000", "-FocalPlaneYResolution=2000",
         "-FocalPlaneResolutionUnit#=2", "-ExifImageWidth=60", "-ExifImageHeight=40")


def sensor(path) -> tuple[float, float]:
    """(across, down) in inches: the sensor the file's EXIF records under its frame."""
    t = exiftool(path, "ExifImageWidth", "ExifImageHeight", "FocalPlaneXResolution", "FocalPlaneYResolution",
                 "ImageWidth", "ImageHeight")
    w, h = t.get("ExifImageWidth", t["ImageWidth"]), t.get("ExifImageHeight", t["ImageHeight"])
    return w / t["FocalPlaneXResolution"], h / t["FocalPlaneYResolution"]


@pytest.mark.parametrize("ext", ["jpg", "png", "tif"])
@pytest.mark.parametrize("stored", [(40, 60), (30, 45)], ids=["turned", "turned-and-smaller"])
def test_a_losslessly_turned_photo_s_copy_turns_its_sensor(tmp_path, capsys, ext, stored):
    """40 x 60 pixels under a 60 x 40 frame; or 30 x 45, the same made smaller by a tool that keeps the EXIF."""
    source = photo(tmp_path / "turned.jpg", *stored, "-Orientation#=1", *PLANE)
    assert sensor(source) == pytest.approx((60 / 1000, 40 / 2000), rel=1e-12)  # (as exiftool reads it)
    out = tmp_path / f"copy.{ext}"
    code, err = run(capsys, "convert", source, "-o", out, "-q")
    assert code == 0, err
    across, down = sensor(source)
    assert sensor(out) == pytest.approx((down, across), rel=1e-9)  # (exiftool prints 10 digits)


def test_a_heic_shown_turned_gives_its_copy_a_turned_sensor(tmp_path, capsys):
    pillow_heif = pytest.importorskip("pillow_heif")
    from PIL import Image

    pillow_heif.register_heif_opener()
    exif = Image.Exif()
    exif[0x010F], exif[0x0112] = "Acme", 6  # Orientation 6: pillow-heif stores it as the HEIF's irot
    ifd = exif.get_ifd(0x8769)
    ifd.update({0x920A: 10.0, 0xA20E: 1000.0, 0xA20F: 2000.0, 0xA210: 2, 0xA002: 60, 0xA003: 40})
    source = tmp_path / "turned.heic"
    Image.fromarray(np.full((40, 60, 3), 128, np.uint8)).save(source, exif=exif.tobytes())
    out = tmp_path / "copy.jpg"
    code, err = run(capsys, "convert", source, "-o", out, "-q")
    assert code == 0, err
    t = exiftool(out, "ImageWidth", "ImageHeight")
    assert (t["ImageWidth"], t["ImageHeight"]) == (40, 60)  # (shown turned: libheif applies the irot)
    assert sensor(out) == pytest.approx((40 / 2000, 60 / 1000), rel=1e-9)
