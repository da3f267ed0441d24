"""``--from exif`` over several photos at once: each photo's field of view is said on a note led by that photo's
name (``lenslab warp: note: PHOTO: source lens from the file's EXIF: ...``), so a batch says which field is whose;
the field is the 35 mm equivalent's by the diagonal, transcribed in float64 (``fov_formula``)."""

from __future__ import annotations

import re

import pytest

from lenslab.cli.main import main

pytest.importorskip("PIL.Image")
from tests.lenses.test_exif_view import fov_formula, write_photo  # noqa: E402


def test_each_photos_note_names_it_and_gives_its_own_field(tmp_path, capsys):
    photos = tmp_path / "photos"
    photos.mkdir()
    lenses = {"wide.jpg": (160, 120, 24), "tele.jpg": (120, 160, 77)}  # w, h, 35 mm equivalent
    for name, (w, h, f35) in lenses.items():
        write_photo(photos / name, w, h, focal35=f35, quality=95)
    assert main(["warp", str(photos), "-o", str(tmp_path / "out"), "--from", "exif", "--to", "equirect",
                 "--size", "64x32", "--format", "exr", "-q"]) == 0
    err = capsys.readouterr().err
    for name, (w, h, f35) in lenses.items():
        found = re.findall(rf"^lenslab warp: note: \S*{re.escape(name)}: source lens from the file's EXIF: "
                           r"perspective:fov=([0-9.]+)", err, re.MULTILINE)
        assert len(found) == 1, err
        assert float(found[0]) == pytest.approx(fov_formula(f35, w, h), abs=1e-9)  # 12 significant digits
    assert "lenslab: source lens" not in err  # no line that names no file
