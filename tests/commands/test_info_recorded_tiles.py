"""``lenslab info`` of a grid whose tiles are recorded in the file (a warp to ``tiled:2x1,tiles=cams.toml``) names
each tile's lens and pose: its ``lens: tiled:2x1`` alone, pasted back, is two 90-degree perspective tiles, another
lens. The tiles expected are those of the tiles file the test writes; a grid of the default tiles gets no such
lines, as its spec says it all."""

from __future__ import annotations

import numpy as np

from lenslab.cli.main import main
from lenslab.io import write


def _info(path, capsys) -> str:
    capsys.readouterr()
    assert main(["info", str(path)]) == 0
    return capsys.readouterr().out


def test_info_names_the_recorded_tiles(tmp_path, capsys):
    cams = tmp_path / "cams.toml"
    cams.write_text('[[tiles]]\nlens = "fisheye:fov=190"\nyaw = 0\n[[tiles]]\nlens = "fisheye:fov=190"\nyaw = 180\n')
    src = tmp_path / "pano.exr"
    write(src, np.full((64, 128, 3), 0.5, np.float32))
    grid = tmp_path / "grid.exr"
    assert main(["warp", str(src), "-o", str(grid), "--to", f"tiled:2x1,tiles={cams}", "--size", "128x64", "-q"]) == 0
    cams.unlink()  # the file alone records the tiles
    out = _info(grid, capsys)
    assert "  lens: tiled:2x1" in out
    tiles = [line.strip() for line in out.splitlines() if line.startswith("    ") and "fisheye:fov=190" in line]
    assert len(tiles) == 2, out
    assert tiles[0].startswith("0: fisheye:fov=190") and "yaw 0," in tiles[0]
    assert tiles[1].startswith("1: fisheye:fov=190") and "yaw 180," in tiles[1]
    assert "give the file itself as the lens" in out


def test_default_tiles_need_no_lines(tmp_path, capsys):
    src = tmp_path / "pano.exr"
    write(src, np.full((64, 128, 3), 0.5, np.float32))
    grid = tmp_path / "grid.exr"
    assert main(["warp", str(src), "-o", str(grid), "--to", "tiled:2x2", "--size", "64x64", "-q"]) == 0
    out = _info(grid, capsys)
    assert "  lens: tiled:2x2" in out
    assert not [line for line in out.splitlines() if line.startswith("  tiles")]
