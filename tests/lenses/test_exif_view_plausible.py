"""``--from exif`` refuses, in one line, a 35 mm equivalent no camera has: a focal plane whose sensor is no
camera's (a copy made smaller without its PixelXDimension, where the image's own pixels are taken for the
sensor's: exiftool then reads no ``FocalLength35efl`` either, its ``CalcScaleFactor35efl`` keeping sensors of a
diagonal from 1 to 100 mm), and focal lengths beyond Exif's ``FocalLengthIn35mmFilm`` (a SHORT: 1 to 65535 mm)
from an XMP packet or from the focal plane, whose field of view is no pinhole's (``perspective:fov=180`` or
``0``, which the lens then refused without naming the photo)."""

from __future__ import annotations

import json
import shutil
import subprocess

import numpy as np
import pytest

from lenslab.errors import LensError
from lenslab.lenses.exif_view import exif_view

pytest.importorskip("PIL.Image")
from PIL import Image  # noqa: E402
from PIL.TiffImagePlugin import IFDRational  # noqa: E402

from tests.lenses.test_exif_view import write_photo  # noqa: E402

EXIFTOOL = shutil.which("exiftool")


def _exiftool_focal35(path) -> float | None:
    out = subprocess.run([EXIFTOOL, "-j", "-n", "-FocalLength35efl", "-ScaleFactor35efl", str(path)],
                         capture_output=True, text=True, check=True, timeout=60).stdout
    tags = json.loads(out)[0]
    return float(tags["FocalLength35efl"]) if "ScaleFactor35efl" in tags else None


def _refusal(path, size) -> str:
    with pytest.raises(LensError) as err:
        exif_view(path, size)
    text = str(err.value)
    assert "\n" not in text and str(path) in text and "--from perspective:fov=" in text
    return text


@pytest.mark.skipif(EXIFTOOL is None, reason="exiftool (Debian's libimage-exiftool-perl) not installed")
@pytest.mark.parametrize("diagonal_mm", [0.43, 0.9, 5.0, 43.27, 90.0, 120.0, 400.0])
def test_a_focal_plane_of_no_cameras_sensor_is_refused_where_exiftool_reads_no_equivalent(tmp_path, diagonal_mm):
    """A 150 x 100 image with no PixelXDimension, FocalLength 6.81 mm and a focal plane resolution putting its
    diagonal at ``diagonal_mm``: lenslab reads exiftool's 35 mm equivalent where exiftool reads one, and refuses
    (naming the sensor it would be) where exiftool reads none."""
    px_per_mm = np.hypot(150.0, 100.0) / diagonal_mm
    xres = IFDRational(round(px_per_mm * 25.4 * 10**6), 10**6)
    path = write_photo(tmp_path / "p.jpg", 150, 100, focal=6.81, plane=(xres, xres, 2, None), quality=95)
    expected = _exiftool_focal35(path)
    if expected is None:
        assert "sensor" in _refusal(path, (150, 100))
    else:
        assert exif_view(path, (150, 100)).focal35 == pytest.approx(expected, rel=1e-9)
    assert (expected is None) == (not 1.0 < diagonal_mm < 100.0)


def _xmp_photo(path, props: dict):
    xmp = ('<x:xmpmeta xmlns:x="adobe:ns:meta/"><rdf:RDF xmlns:rdf="http://www.w3.org/1999/02/22-rdf-syntax-ns#">'
           '<rdf:Description xmlns:exif="http://ns.adobe.com/exif/1.0/" '
           + " ".join(f'exif:{k}="{v}"' for k, v in props.items()) + "/></rdf:RDF></x:xmpmeta>")
    Image.fromarray(np.zeros((100, 150, 3), np.uint8)).save(path, xmp=xmp.encode())
    return path


@pytest.mark.parametrize("props", [
    {"FocalLengthIn35mmFilm": "1e-300"},  # gave perspective:fov=180
    {"FocalLengthIn35mmFilm": "0.5"},
    {"FocalLengthIn35mmFilm": "1e300"},  # gave perspective:fov=2.06e-297
    {"FocalLengthIn35mmFilm": "70000"},
    {"FocalLength": "1e308", "FocalPlaneXResolution": "1", "FocalPlaneResolutionUnit": "4"},  # gave fov=0
])
def test_an_equivalent_beyond_exifs_range_is_refused_naming_the_photo(tmp_path, props):
    """Exif's FocalLengthIn35mmFilm is a SHORT: 1 to 65535 mm. Beyond it (from XMP, or FocalLength over the focal
    plane), the one-line refusal names the photo and the equivalent."""
    path = _xmp_photo(tmp_path / "p.jpg", props)
    assert "35 mm equivalent" in _refusal(path, (150, 100))


@pytest.mark.parametrize("f35", ["1", "65535", "26.5"])
def test_the_ends_of_exifs_range_are_read(tmp_path, f35):
    """The field across a 3:2 image: 2 atan(18 / f35), the 36 mm side of the 35 mm frame (float64 here)."""
    path = _xmp_photo(tmp_path / "p.jpg", {"FocalLengthIn35mmFilm": f35})
    assert exif_view(path, (150, 100)).fov == pytest.approx(np.degrees(2 * np.arctan(18.0 / float(f35))), abs=1e-9)


def test_info_says_why_not_where_it_printed_a_spec_that_fails(tmp_path, capsys):
    from lenslab.cli.main import main

    path = _xmp_photo(tmp_path / "p.jpg", {"FocalLengthIn35mmFilm": "1e-300"})
    assert main(["info", str(path)]) == 0
    out = capsys.readouterr().out
    assert "perspective:fov=180" not in out and "35 mm equivalent" in out


@pytest.mark.skipif(EXIFTOOL is None, reason="exiftool (Debian's libimage-exiftool-perl) not installed")
@pytest.mark.parametrize("orientation", [1, 3, 5, 6, 7, 8])
def test_a_turned_photos_focal_plane_is_its_stored_frames(tmp_path, orientation):
    """FocalPlaneXResolution counts pixels across the stored width: a 300 x 200 JPEG at 1000 and 500 pixels per cm
    has a 3 x 4 mm sensor however its orientation shows it (5 to 8: 200 x 300), so the 35 mm equivalent is
    exiftool's (from the stored ImageWidth and ImageHeight) for each."""
    from lenslab.io import read

    plane = (IFDRational(1000), IFDRational(500), 3, None)
    path = write_photo(tmp_path / "p.jpg", 300, 200, focal=6.81, plane=plane, orientation=orientation, quality=95)
    shown = tuple(read(path)[1]["size"])
    assert shown == ((200, 300) if orientation >= 5 else (300, 200))
    expected = _exiftool_focal35(path)
    assert expected == pytest.approx(6.81 * np.hypot(36, 24) / 5.0, rel=1e-12)
    assert exif_view(path, shown).focal35 == pytest.approx(expected, rel=1e-12)
