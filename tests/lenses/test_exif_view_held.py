"""``--from exif`` on a photo whose EXIF records a focal length that is no lens's (FocalLength 0 or negative,
FocalLengthIn35mmFilm 0, which Exif 2.3 defines as "unknown", FocalPlaneXResolution 0) says what the file holds;
"no TAG" stays for a tag the file does not record. It used to say "no FocalLengthIn35mmFilm nor FocalLength" of
a file that records both.

The values a message names are the ones exiftool (Debian's libimage-exiftool-perl) reads from the file Pillow
wrote; whether a tag is recorded at all is exiftool's answer too.
"""

from __future__ import annotations

import json
import shutil
import subprocess

import pytest

from lenslab.cli.main import main as lenslab
from lenslab.errors import LensError

pytest.importorskip("PIL.Image")
from PIL.TiffImagePlugin import IFDRational  # noqa: E402

from tests.lenses.test_exif_view import view_of, write_photo  # noqa: E402

EXIFTOOL = shutil.which("exiftool")
pytestmark = pytest.mark.skipif(EXIFTOOL is None, reason="exiftool (Debian's libimage-exiftool-perl) not installed")
TAGS = {"FocalLength": "FocalLength", "FocalLengthIn35mmFormat": "FocalLengthIn35mmFilm",
        "FocalPlaneXResolution": "FocalPlaneXResolution"}


def recorded(path) -> dict:
    """The tags exiftool reads from ``path`` (numbers, -n), by their Exif names."""
    out = subprocess.run([EXIFTOOL, "-j", "-n", *(f"-{t}" for t in TAGS), str(path)], capture_output=True, text=True,
                         check=True, timeout=60).stdout
    return {TAGS[k]: float(v) for k, v in json.loads(out)[0].items() if k in TAGS}


def refusal(path) -> str:
    with pytest.raises(LensError) as err:
        view_of(path, (150, 100))
    text = str(err.value)
    assert "\n" not in text and text.startswith(f"{path}: --from exif needs the photo's 35 mm equivalent focal length")
    return text


@pytest.mark.parametrize("tags", [{"focal35": 0}, {"focal": 0.0}, {"focal": -5.0}, {"focal35": 0, "focal": 0.0},
                                  {"focal": -4.5, "focal35": 0}])
def test_a_focal_length_of_no_lens_is_named_with_its_value(tmp_path, tags):
    path = write_photo(tmp_path / "p.jpg", 150, 100, quality=95, **tags)
    held = recorded(path)
    assert set(held) == {"FocalLengthIn35mmFilm" if k == "focal35" else "FocalLength" for k in tags}
    text = refusal(path)
    if "FocalLengthIn35mmFilm" in held:
        assert held["FocalLengthIn35mmFilm"] == 0
        assert "FocalLengthIn35mmFilm 0 (Exif's 'unknown')" in text
    else:
        assert "no FocalLengthIn35mmFilm" in text
    if "FocalLength" in held:
        assert held["FocalLength"] <= 0
        assert f"FocalLength {held['FocalLength']:g} mm (no lens's)" in text
    else:
        assert "no FocalLength;" in text
    assert "missing" not in text and "nor" not in text


def test_an_unknown_35mm_equivalent_beside_a_focal_length_without_its_plane(tmp_path):
    path = write_photo(tmp_path / "p.jpg", 150, 100, focal35=0, focal=6.81, quality=95)
    assert recorded(path) == {"FocalLengthIn35mmFilm": 0, "FocalLength": 6.81}
    assert ("its EXIF has FocalLengthIn35mmFilm 0 (Exif's 'unknown'), and no FocalPlaneXResolution to go with "
            "FocalLength 6.81 mm;") in refusal(path)


def test_a_focal_plane_resolution_of_zero_is_named(tmp_path):
    path = write_photo(tmp_path / "p.jpg", 150, 100, focal=6.81, plane=(IFDRational(0), IFDRational(0), 3, None),
                       quality=95)
    assert recorded(path)["FocalPlaneXResolution"] == 0
    assert ("its EXIF has no FocalLengthIn35mmFilm, and FocalPlaneXResolution 0 (no resolution) to go with "
            "FocalLength 6.81 mm;") in refusal(path)


def test_a_photo_with_neither_tag_still_says_no(tmp_path):
    path = write_photo(tmp_path / "p.jpg", 150, 100, quality=95)
    assert recorded(path) == {}
    assert "its EXIF has no FocalLengthIn35mmFilm nor FocalLength;" in refusal(path)


def test_the_warp_says_it_in_one_line_as_a_failed_input(tmp_path, capsys):
    path = write_photo(tmp_path / "p.jpg", 150, 100, focal=0.0, quality=95)
    out = tmp_path / "pano.exr"
    capsys.readouterr()
    assert lenslab(["warp", str(path), "-o", str(out), "--from", "exif", "--to", "equirect", "--size", "64x32"]) == 1
    assert capsys.readouterr().err == (
        f"lenslab warp: error: {path}: --from exif needs the photo's 35 mm equivalent focal length; its EXIF has "
        "FocalLength 0 mm (no lens's) and no FocalLengthIn35mmFilm; give the lens, e.g. --from perspective:fov=DEGREES\n")
    assert not out.exists()


def test_an_xmp_packets_focal_lengths_of_no_lens_are_named(tmp_path):
    """The same tags in an XMP packet (exif: properties, written as text: FocalLength "0/1", a rational of 0)."""
    import numpy as np
    from PIL import Image

    xmp = ('<x:xmpmeta xmlns:x="adobe:ns:meta/"><rdf:RDF xmlns:rdf="http://www.w3.org/1999/02/22-rdf-syntax-ns#">'
           '<rdf:Description rdf:about="" xmlns:exif="http://ns.adobe.com/exif/1.0/" exif:FocalLength="0/1" '
           'exif:FocalLengthIn35mmFilm="0"/></rdf:RDF></x:xmpmeta>')
    path = tmp_path / "p.jpg"
    Image.fromarray(np.zeros((100, 150, 3), np.uint8)).save(path, xmp=xmp.encode(), quality=95)
    assert recorded(path) == {"FocalLength": 0, "FocalLengthIn35mmFilm": 0}
    assert "FocalLengthIn35mmFilm 0 (Exif's 'unknown') and FocalLength 0 mm (no lens's);" in refusal(path)
