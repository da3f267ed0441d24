"""A warp without ``--size`` whose default size (180 degrees at the source's pixels per degree) would be more than
an image can be makes the limited size every large default gets (twice the source's pixels), for every output lens
alike, and its note says why the source's resolution cannot be kept instead of offering a --size lenslab refuses.

A 1024 x 256 band of latitudes 0 to 0.01 degrees holds 256 / 0.01 = 25600 pixels a degree, so 180 degrees of it
would be 4608000 rows, far beyond the 131072 pixels a side lenslab writes. The expected sizes come from the band's
geometry here; the output's size is read back by OpenEXR's own binding."""

from __future__ import annotations

import math

import numpy as np
import OpenEXR
import pytest

from lenslab.cli.main import main
from lenslab.io import write

ROWS, COLS, LAT = 256, 1024, 0.01  # the band's rows and columns, and the degrees of latitude the rows span
PPD = ROWS / LAT  # 25600 pixels a degree
FULL = round(180 * PPD)  # 4608000 rows for 180 degrees
LIMIT = 2 * COLS * ROWS  # twice the source's pixels


def expected(to: str):
    """The limited size in the lens's shape (fisheye square, equirect 2:1), or None for the cube map (below)."""
    if to == "equirect":
        kept = math.floor(math.sqrt(LIMIT / 2))
        return 2 * kept, kept
    if to.startswith("fisheye"):
        kept = math.floor(math.sqrt(LIMIT))
        return kept, kept
    return None


@pytest.mark.parametrize("to, full", [("fisheye:fov=180", f"{FULL} x {FULL}"),
                                      ("equirect", f"{2 * FULL} x {FULL}"),
                                      ("cubemap", None)])
def test_a_default_beyond_any_image_is_limited_and_said(tmp_path, capsys, to, full):
    src = tmp_path / "band.exr"
    write(src, np.full((ROWS, COLS, 3), 0.5, np.float32))
    out = tmp_path / "out.exr"
    capsys.readouterr()
    assert main(["warp", str(src), "-o", str(out), "--from", f"equirect:lat_min=0,lat_max={LAT}", "--to", to]) == 0
    with OpenEXR.File(str(out)) as f:
        (x0, y0), (x1, y1) = f.header()["dataWindow"]
    size = (int(x1 - x0 + 1), int(y1 - y0 + 1))
    if expected(to):
        assert size == expected(to)
    else:  # a 3x2 cube map of square 90-degree faces, the largest within the limit (to a face's rounding)
        face = size[0] // 3
        assert size == (3 * face, 2 * face) and 6 * face * face <= LIMIT
        assert face >= math.floor(math.sqrt(LIMIT / 6)) - 1
    notes = [line for line in capsys.readouterr().err.splitlines() if "without --size" in line]
    assert len(notes) == 1, notes
    assert f"the output is {size[0]} x {size[1]}" in notes[0]
    assert f"the source's {PPD:.3g} pixels per degree would make it" in notes[0]
    assert "more than an image can be" in notes[0] and notes[0].endswith("give --size WxH for another size")
    assert (f" {full}," in notes[0]) if full else " x " not in notes[0].split("would make it")[1]
    assert "--size 4608000" not in notes[0]  # never a --size that would be refused
