"""``--from exif`` says which lens each photo gave, naming the photo: in a batch of photos of other focal lengths the
lines came in the order the threads finished, each "lenslab: source lens from the file's EXIF: ..." with no name,
so a user could not tell which photo was read as which lens."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

Image = pytest.importorskip("PIL.Image")


def photo(path, mm35: int) -> None:
    """A 160 x 120 JPEG whose EXIF gives only its 35 mm equivalent focal length (FocalLengthIn35mmFilm, 0xA405)."""
    ex = Image.Exif()
    ex.get_ifd(0x8769)[0xA405] = mm35
    Image.fromarray(np.full((120, 160, 3), 128, np.uint8)).save(path, exif=ex, quality=95)


def fov_across(mm35: float, w: int, h: int) -> float:
    """The horizontal field in degrees of a pinhole with that 35 mm equivalent (its diagonal against the 43.27 mm of
    36 x 24 mm film), transcribed in float64 as CIPA DC-008 defines the equivalent."""
    half_diagonal = math.hypot(36.0, 24.0) / 2
    return math.degrees(2 * math.atan(half_diagonal / mm35 * w / math.hypot(w, h)))


def test_each_photo_of_a_batch_is_named_with_the_lens_its_exif_gives(tmp_path, capsys):
    from lenslab.cli.main import main

    photo(tmp_path / "wide.jpg", 24)
    photo(tmp_path / "normal.jpg", 50)
    assert main(["warp", str(tmp_path / "wide.jpg"), str(tmp_path / "normal.jpg"), "-o", str(tmp_path / "out"),
                 "--from", "exif", "--to", "equirect", "--size", "64x32", "--jobs", "2"]) == 0
    said = {Path(m.group(1)).name: float(m.group(2)) for m in re.finditer(
        r"^lenslab warp: note: (.+?): source lens from the file's EXIF: perspective:fov=([0-9.]+)", capsys.readouterr().err,
        re.MULTILINE)}
    assert set(said) == {"wide.jpg", "normal.jpg"}, said
    for name, mm in (("wide.jpg", 24), ("normal.jpg", 50)):
        assert said[name] == pytest.approx(fov_across(mm, 160, 120), abs=1e-6)  # (the spec's 10 decimals)
