"""``--from exif``'s field of view against exiftool's Composite tags (Debian's libimage-exiftool-perl; where it is
not installed these skip, and tests/lenses/test_exif_view.py holds the formula, published pairs and the sensor's
pinhole): ``FocalLength35efl`` (its 35 mm equivalent, from FocalLengthIn35mmFilm or from the focal plane's
resolution and the frame, by the 43.27 mm diagonal; none where that sensor is under 1 or over 100 mm across) and
``FOV``, which exiftool gives across the 36 mm side of the 35 mm frame: the field across a 3:2 landscape photo,
which ``--from exif`` must match."""

from __future__ import annotations

import json
import math
import shutil
import subprocess
from pathlib import Path

import pytest

from lenslab.errors import LensError

pytest.importorskip("PIL.Image")
from PIL.TiffImagePlugin import IFDRational  # noqa: E402

from tests.lenses.test_exif_view import fov_formula, view_of, write_photo  # noqa: E402

EXIFTOOL = shutil.which("exiftool")
pytestmark = pytest.mark.skipif(EXIFTOOL is None, reason="exiftool (Debian's libimage-exiftool-perl) not installed")
#: exiftool's FOV turns radians to degrees with pi written 3.14159 (its Composite FOV: "$fd2 * 360 / 3.14159")
EXIFTOOL_PI = 3.14159
PIXEL_PHOTO = Path("formats") / "oiio-images" / "ultrahdr_sky.jpg"  # in ../shared/data


def exiftool(path) -> dict:
    out = subprocess.run([EXIFTOOL, "-j", "-n", "-FOV", "-FocalLength35efl", str(path)], capture_output=True,
                         text=True, check=True, timeout=60).stdout
    return json.loads(out)[0]


def exiftool_fov(tags: dict) -> float:
    """exiftool's FOV with its pi put right (a relative 8.4e-7 of it)."""
    return float(tags["FOV"]) * EXIFTOOL_PI / math.pi


@pytest.mark.parametrize("f35", [14, 24, 50, 200])
def test_focal_length_in_35mm_film_on_a_3_2_photo_matches_exiftool(tmp_path, f35):
    path = write_photo(tmp_path / "p.jpg", 150, 100, focal35=f35, focal=6.81, quality=95)
    tags, view = exiftool(path), view_of(path, (150, 100))
    assert view.focal35 == pytest.approx(float(tags["FocalLength35efl"]), rel=1e-12)
    # exiftool prints 15 digits: the two agree to 1e-9 degree
    assert view.fov == pytest.approx(exiftool_fov(tags), abs=1e-9)


@pytest.mark.parametrize("unit, per_mm", [(2, 25.4), (3, 10.0)])
def test_the_focal_plane_route_matches_exiftool(tmp_path, unit, per_mm):
    """FocalLength 6.81 mm on a 9.6 x 6.4 mm sensor recorded as 4000 x 2667 pixels: exiftool's 35 mm equivalent
    (its ScaleFactor35efl from the focal plane) and its FOV."""
    xres = IFDRational(round(4000 / 9.6 * per_mm * 1000), 1000)
    path = write_photo(tmp_path / "p.jpg", 150, 100, focal=6.81, plane=(xres, xres, unit, (4000, 2667)), quality=95)
    tags, view = exiftool(path), view_of(path, (150, 100))
    assert view.focal35 == pytest.approx(float(tags["FocalLength35efl"]), rel=1e-9)
    # the 150 x 100 copy is 1.5:1, the 4000 x 2667 frame 1.49981:1: exiftool's field is across that frame's 36 mm
    # equivalent width, this one across the copy's; they differ by the frames' shapes, < 1e-4 degree here
    assert view.fov == pytest.approx(exiftool_fov(tags), abs=1e-4)


@pytest.mark.shared_data
def test_a_real_pixel_photo_has_exiftools_equivalent_and_its_own_aspect(shared_data):
    """The Pixel 6 Pro's 4080 x 3072 photo: the 35 mm equivalent exiftool reads (24 mm), and the field across its
    4:3 width, narrower than exiftool's across a 3:2 frame's 36 mm by the formula's W / hypot(W, H) against 36/43.27."""
    photo = shared_data / PIXEL_PHOTO
    tags, view = exiftool(photo), view_of(photo, (4080, 3072))
    assert view.focal35 == float(tags["FocalLength35efl"]) == 24
    assert view.fov == pytest.approx(fov_formula(24, 4080, 3072), abs=1e-9)
    half = math.tan(math.radians(exiftool_fov(tags)) / 2) * math.hypot(36, 24) / 36 * 4080 / math.hypot(4080, 3072)
    assert view.fov == pytest.approx(math.degrees(2 * math.atan(half)), abs=1e-9)


def _refusal(path, size) -> str:
    with pytest.raises(LensError) as err:
        view_of(path, size)
    text = str(err.value)
    assert "\n" not in text and str(path) in text and "--from perspective:fov=" in text
    return text


@pytest.mark.parametrize("diagonal_mm", [0.43, 0.9, 5.0, 43.27, 90.0, 120.0, 400.0])
def test_a_focal_plane_of_no_cameras_sensor_is_refused_where_exiftool_reads_no_equivalent(tmp_path, diagonal_mm):
    """A 150 x 100 image with no PixelXDimension (a copy made smaller has its own pixels taken for the sensor's),
    FocalLength 6.81 mm and a focal plane resolution putting its diagonal at ``diagonal_mm``: lenslab reads
    exiftool's 35 mm equivalent where exiftool reads one (its CalcScaleFactor35efl keeps sensors 1 to 100 mm
    across), and refuses in one line, naming the sensor it would be, where exiftool reads none."""
    px_per_mm = math.hypot(150.0, 100.0) / diagonal_mm
    xres = IFDRational(round(px_per_mm * 25.4 * 10**6), 10**6)
    path = write_photo(tmp_path / "p.jpg", 150, 100, focal=6.81, plane=(xres, xres, 2, None), quality=95)
    tags = exiftool(path)
    known = "FOV" in tags  # (exiftool's FOV needs its ScaleFactor35efl; FocalLength35efl is FocalLength without it)
    if known:
        assert view_of(path, (150, 100)).focal35 == pytest.approx(float(tags["FocalLength35efl"]), rel=1e-9)
    else:
        assert "sensor" in _refusal(path, (150, 100))
    assert known == (1.0 < diagonal_mm < 100.0)


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
    expected = float(exiftool(path)["FocalLength35efl"])
    assert expected == pytest.approx(6.81 * math.hypot(36, 24) / 5.0, rel=1e-12)
    assert view_of(path, shown).focal35 == pytest.approx(expected, rel=1e-12)
