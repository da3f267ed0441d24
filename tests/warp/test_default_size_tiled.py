"""A warp without ``--size`` into a tiled grid makes square tiles of whole pixels at the source's resolution, in any
grid: a 90-degree perspective tile (the default tiles) spans 90 of the 180 degrees a source of R rows holds, so it
is R * 90 / 180 pixels (rounded down), as a cube face is; a tile of a 190-degree fisheye R * 190 / 180. The sizes
are worked out here from those angles and read back by OpenEXR's own binding. Before, the grid took the source's
R x R whatever its layout: a 3x1 grid was refused for a size the user never gave, an odd R was refused too, and
a 4x1 grid had tiles four times as tall as wide."""

from __future__ import annotations

import numpy as np
import OpenEXR
import pytest

from lenslab.cli.main import main
from lenslab.io import write


def _size(path) -> tuple[int, int]:
    with OpenEXR.File(str(path)) as f:
        (x0, y0), (x1, y1) = f.header()["dataWindow"]
    return int(x1 - x0 + 1), int(y1 - y0 + 1)


@pytest.mark.parametrize("rows", [512, 485])
@pytest.mark.parametrize("grid", ["2x2", "3x1", "4x1", "1x3", "3x2"])
def test_a_grid_takes_square_tiles_at_the_source_resolution(tmp_path, rows, grid):
    src = tmp_path / "pano.exr"
    write(src, np.full((rows, 2 * rows, 3), 0.5, np.float32))
    out = tmp_path / "grid.exr"
    assert main(["warp", str(src), "-o", str(out), "--to", f"tiled:{grid}", "-q"]) == 0
    cols, grid_rows = (int(v) for v in grid.split("x"))
    tile = rows * 90 // 180
    assert _size(out) == (cols * tile, grid_rows * tile)


def test_a_tiles_file_of_fisheyes_takes_their_field(tmp_path):
    cams = tmp_path / "cams.toml"
    cams.write_text('[[tiles]]\nlens = "fisheye:fov=190"\nyaw = 0\n[[tiles]]\nlens = "fisheye:fov=190"\nyaw = 180\n')
    src = tmp_path / "pano.exr"
    write(src, np.full((360, 720, 3), 0.5, np.float32))
    out = tmp_path / "grid.exr"
    assert main(["warp", str(src), "-o", str(out), "--to", f"tiled:2x1,tiles={cams}", "-q"]) == 0
    tile = 360 * 190 // 180  # 380: the fisheye's 190 degrees at 2 pixels a degree
    assert _size(out) == (2 * tile, tile)
