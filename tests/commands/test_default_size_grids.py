"""A warp without ``--size`` from a tiled grid or a padded equi-angular cube map keeps the angular resolution of
its tiles or faces, whatever the layout: 256-pixel tiles of 90-degree perspective cameras give an equirect of
512 rows (180 degrees at 256 / 90 pixels per degree) from a 4x1 strip, a 1x4 column and a 2x2 grid alike (it
used to come from the image's rows: 256, 1024 and 512), and an EAC map's faces without v360's padding of 2
pixels round each row hold 90 degrees (404 rows: faces of 198 rows, 396 rows of 180 degrees, not 404).

The expected sizes come from the geometry alone: a 90-degree tile or face of n rows has n / 90 rows per degree.
"""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import read, write


def _warp(tmp_path, source: str, size: tuple[int, int]) -> tuple[int, int]:
    src = tmp_path / "src.exr"
    write(src, np.full((size[1], size[0], 3), 0.25, np.float32))
    out = tmp_path / "pano.exr"
    assert main(["warp", str(src), "-o", str(out), "--from", source, "--to", "equirect", "-q"]) == 0
    return tuple(read(out)[1]["size"])


@pytest.mark.parametrize("grid,size", [("4x1", (1024, 256)), ("1x4", (256, 1024)), ("2x2", (512, 512))])
def test_a_grid_of_tiles_gives_the_equirect_of_its_tiles_resolution(tmp_path, grid, size):
    rows = round(180 * 256 / 90)  # tiles of 256 rows over their 90 degrees
    assert _warp(tmp_path, f"tiled:{grid}", size) == (2 * rows, rows)


def test_an_eac_map_s_padding_is_not_resolution(tmp_path):
    face_rows = 404 // 2 - 2 * 2  # each row of faces framed by 2 pixels above and below
    rows = round(180 * face_rows / 90)
    assert _warp(tmp_path, "eac:pad=2", (606, 404)) == (2 * rows, rows)
