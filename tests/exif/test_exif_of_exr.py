"""An EXR's camera EXIF under the names OpenImageIO writes (``Make``, ``Model``, ``Exif:FocalLengthIn35mmFilm``,
``Exif:FocalPlaneXResolution``...): ``--from exif`` and ``lenslab info`` read them from an EXR OpenImageIO made of a
photo, ``lenslab convert`` carries them on to a JPEG, and an EXR's data window written alone (a part of its frame)
keeps its pixel pitch and loses the 35 mm equivalent, which no longer holds."""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest

from tests.exif.exif_tools import exiftool, from_exif_fov, needs_exiftool, oiio_attribute, photo, run, shown_fov

oiio = pytest.importorskip("OpenImageIO")
pytestmark = needs_exiftool
SHOT = ("-Make=Acme", "-Model=Upright Two", "-FocalLength=4.25", "-FocalLengthIn35mmFormat=28")


def oiio_exr(source, out):
    """``out``: the EXR OpenImageIO writes of ``source`` (its EXIF as header attributes under its own names)."""
    buf = oiio.ImageBuf(str(source))
    assert buf.write(str(out)), oiio.geterror()
    assert oiio_attribute(out, "Exif:FocalLengthIn35mmFilm") == 28  # (OpenImageIO wrote it so)
    return out


def test_from_exif_reads_an_exr_openimageio_made_of_a_photo(tmp_path, capsys):
    source = photo(tmp_path / "p.jpg", 64, 48, *SHOT)
    exr = oiio_exr(source, tmp_path / "oiio.exr")
    assert from_exif_fov(capsys, exr, tmp_path) == pytest.approx(shown_fov(exiftool(source, "FOV"), 64, 48),
                                                                 abs=1e-9)
    said = json.loads(info_json(capsys, exr))[0]["lens_metadata"]
    assert "Acme" in said["found"] and "Upright Two" in said["found"]
    assert float(re.search(r"fov=([0-9.]+)", said["exif"]).group(1)) == pytest.approx(
        shown_fov(exiftool(source, "FOV"), 64, 48), abs=1e-9)


def info_json(capsys, path) -> str:
    from lenslab.cli.main import main

    capsys.readouterr()
    assert main(["info", str(path), "--json"]) == 0
    return capsys.readouterr().out


def test_convert_carries_an_openimageio_exr_s_camera_to_a_jpeg(tmp_path, capsys):
    source = photo(tmp_path / "p.jpg", 64, 48, *SHOT)
    exr = oiio_exr(source, tmp_path / "oiio.exr")
    code, err = run(capsys, "convert", exr, "-o", tmp_path / "back.jpg", "-q")
    assert code == 0, err
    original, back = exiftool(source), exiftool(tmp_path / "back.jpg")
    assert (back["Make"], back["Model"], back["FocalLengthIn35mmFormat"]) == ("Acme", "Upright Two", 28)
    assert back["FocalLength"] == original["FocalLength"] == 4.25  # (OpenImageIO's float, the photo's rational)
    assert (back["ExifImageWidth"], back["ExifImageHeight"]) == (original["ImageWidth"], original["ImageHeight"])
    assert back["FOV"] == original["FOV"]


def windowed_exr(path):
    """An EXR OpenImageIO writes: a 40 x 30 data window at (10, 5) inside a 60 x 40 frame of FocalLength 6.81 mm and
    a 26 mm equivalent, 80 pixels per cm on the focal plane."""
    spec = oiio.ImageSpec(40, 30, 3, oiio.HALF)
    spec.x, spec.y = 10, 5
    spec.full_x, spec.full_y, spec.full_width, spec.full_height = 0, 0, 60, 40
    for name, value in (("Exif:FocalLength", 6.81), ("Exif:FocalLengthIn35mmFilm", 26), ("Make", "Acme"),
                        ("Exif:FocalPlaneXResolution", 80.0), ("Exif:FocalPlaneYResolution", 80.0),
                        ("Exif:FocalPlaneResolutionUnit", 3), ("Exif:PixelXDimension", 60),
                        ("Exif:PixelYDimension", 40)):
        spec.attribute(name, value)
    buf = oiio.ImageBuf(spec)
    oiio.ImageBufAlgo.fill(buf, (0.5, 0.5, 0.5))
    assert buf.write(str(path)), oiio.geterror()
    return path


def test_an_exr_data_window_written_alone_keeps_the_pixel_pitch(tmp_path, capsys):
    """The data window written alone is a 4 x 3 mm part of the sensor, whose field across its width is
    2 atan(2 / 6.81) (OpenImageIO's float FocalLength, 6.8099999428, the 6.81 it was given); its
    FocalLengthIn35mmFilm (the whole frame's) is left out."""
    windowed_exr(tmp_path / "crop.exr")
    focal = 6.81
    assert oiio_attribute(tmp_path / "crop.exr", "Exif:FocalLength") == float(np.float32(focal))
    code, err = run(capsys, "convert", tmp_path / "crop.exr", "--data-window", "-o", tmp_path / "part.png", "-q")
    assert code == 0, err
    tags = exiftool(tmp_path / "part.png")
    assert "FocalLengthIn35mmFormat" not in tags
    assert (tags["ExifImageWidth"], tags["ExifImageHeight"], tags["FocalPlaneXResolution"]) == (40, 30, 80)
    sensor_width = 40 / 80 * 10.0  # mm
    expected = math.degrees(2 * math.atan(sensor_width / (2 * focal)))
    assert from_exif_fov(capsys, tmp_path / "part.png", tmp_path) == pytest.approx(expected, abs=1e-9)


def test_exr_to_exr_keeps_the_whole_frame_s_tags(tmp_path, capsys):
    """EXR to EXR keeps the data window inside its display window: the frame is the whole 60 x 40 one, so its 35 mm
    equivalent holds and OpenImageIO reads the source's values back (the focal length as the float it was)."""
    windowed_exr(tmp_path / "w.exr")
    code, err = run(capsys, "convert", tmp_path / "w.exr", "-o", tmp_path / "copy.exr", "-q")
    assert code == 0, err
    for name in ("Exif:FocalLengthIn35mmFilm", "Exif:PixelXDimension", "Exif:PixelYDimension", "Make",
                 "Exif:FocalLength", "Exif:FocalPlaneXResolution"):
        assert oiio_attribute(tmp_path / "copy.exr", name) == oiio_attribute(tmp_path / "w.exr", name), name
    spec = oiio.ImageInput.open(str(tmp_path / "copy.exr")).spec()
    assert (spec.x, spec.y, spec.width, spec.full_width) == (10, 5, 40, 60)


def test_an_exr_s_zero_focal_lengths_are_named_with_their_values(tmp_path, capsys):
    """A zero the header holds is named as the file holds it (exiftool reads the JPEG's the same), not as missing."""
    source = photo(tmp_path / "p.jpg", 64, 48, "-FocalLength=0", "-FocalLengthIn35mmFormat=0")
    shot = exiftool(source, "FocalLength", "FocalLengthIn35mmFormat")
    assert (shot["FocalLength"], shot["FocalLengthIn35mmFormat"]) == (0, 0)
    buf = oiio.ImageBuf(str(source))
    assert buf.write(str(tmp_path / "zero.exr")), oiio.geterror()
    assert oiio_attribute(tmp_path / "zero.exr", "Exif:FocalLengthIn35mmFilm") == 0
    code, err = run(capsys, "warp", tmp_path / "zero.exr", "-o", tmp_path / "o.exr", "--from", "exif",
                    "--to", "equirect", "--size", "64x32")
    assert code == 1 and "FocalLengthIn35mmFilm 0 (Exif's 'unknown')" in err and "FocalLength 0 mm" in err, err
