"""A warp without ``--size`` gives the output the source's pixels per degree over the output's own field, measured as
a source's is (rows over the degrees the middle column spans): a 120-degree fisheye from a source of R rows over
180 degrees is R * 120 / 180 pixels, a 90-degree perspective view R * 90 / 180, where it used to take R rows for
any field (a 30-degree view six times the source's resolution); and the note of a limited size gives the --size
that really keeps the source's resolution. The expected sizes are the angles worked out here (the perspective
source's vertical field transcribed from its formula in float64); sizes read back by OpenEXR's own binding."""

from __future__ import annotations

import math

import numpy as np
import OpenEXR
import pytest

from lenslab.cli.main import main
from lenslab.io import write


def _size(path) -> tuple[int, int]:
    with OpenEXR.File(str(path)) as f:
        (x0, y0), (x1, y1) = f.header()["dataWindow"]
    return int(x1 - x0 + 1), int(y1 - y0 + 1)


@pytest.mark.parametrize("to, field", [("fisheye:fov=120", 120), ("fisheye:fov=90", 90),
                                       ("fisheye:fov=180", 180), ("perspective:fov=90", 90),
                                       ("perspective:fov=30", 30), ("fisheye:fov=220", 220)])
def test_the_output_field_at_the_source_resolution(tmp_path, to, field):
    rows = 512
    src = tmp_path / "pano.exr"
    write(src, np.full((rows, 2 * rows, 3), 0.5, np.float32))
    out = tmp_path / "out.exr"
    assert main(["warp", str(src), "-o", str(out), "--to", to, "-q"]) == 0
    side = round(rows * field / 180)
    assert _size(out) == (side, side)


def test_the_note_gives_the_size_that_keeps_the_resolution(tmp_path, capsys):
    """A 70-degree photo of 400 x 300 into a 120-degree fisheye: the photo's rows over its vertical field,
    2 atan(tan(35 deg) * 300 / 400), times 120 degrees; more than twice the photo's pixels, so the default is
    limited and the note names that size."""
    vfov = math.degrees(2 * math.atan(math.tan(math.radians(35)) * 300 / 400))
    keep = round(300 / vfov * 120)
    src = tmp_path / "photo.exr"
    write(src, np.full((300, 400, 3), 0.5, np.float32))
    out = tmp_path / "out.exr"
    capsys.readouterr()
    assert main(["warp", str(src), "-o", str(out), "--from", "perspective:fov=70", "--to", "fisheye:fov=120"]) == 0
    (note,) = [line for line in capsys.readouterr().err.splitlines() if "without --size" in line]
    given = int(note.split("; --size ")[1].split("x")[0])
    assert abs(given - keep) <= 1, (note, keep)  # (the source's own measure rounds to a whole row)
    side = math.floor(math.sqrt(2 * 400 * 300))
    assert _size(out) == (side, side)
