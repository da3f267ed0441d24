"""``lenslab info`` says an EXR's tiling in the words convert's scanline note uses ("64 x 64 tiles, mip-mapped,
7 levels"), not the bindings' repr. Expected values: the tile size in OpenEXR's reading of the header of a file
OpenEXR wrote (one level) or OpenImageIO wrote (mip-mapped), and the level count OpenImageIO finds."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import OpenEXR
import pytest

oiio = pytest.importorskip("OpenImageIO")


def _info(path, *flags):
    run = subprocess.run([sys.executable, "-m", "lenslab", "info", str(path), *flags], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    return run.stdout


def _tiles(path):
    return OpenEXR.File(str(path), header_only=True).parts[0].header["tiles"]


def test_a_tiled_file_written_by_openexr(tmp_path):
    path = tmp_path / "tiled.exr"
    tiles = OpenEXR.TileDescription()
    tiles.xSize, tiles.ySize, tiles.mode = 32, 16, OpenEXR.ONE_LEVEL
    rgb = np.random.default_rng(3).uniform(0, 4, (50, 70, 3)).astype(np.float16)
    OpenEXR.File({"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.tiledimage, "tiles": tiles},
                 {"RGB": rgb}).write(str(path))
    read = _tiles(path)
    words = f"{read.xSize} x {read.ySize} tiles"
    assert words == "32 x 16 tiles"
    lines = [line.strip() for line in _info(path).splitlines() if line.strip().startswith("tiles:")]
    assert lines == [f"tiles: {words}"]
    [doc] = json.loads(_info(path, "--json"))
    assert doc["attributes"]["tiles"] == doc["structure"]["parts"][0]["attributes"]["tiles"] == words


def test_a_mipmapped_file_names_its_levels(tmp_path):
    path = tmp_path / "mip.exr"
    buf = oiio.ImageBuf(oiio.ImageSpec(100, 60, 3, "half"))
    oiio.ImageBufAlgo.fill(buf, (0.5, 0.2, 0.1))
    assert oiio.ImageBufAlgo.make_texture(oiio.MakeTxTexture, buf, str(path), oiio.ImageSpec()), oiio.geterror()
    inp = oiio.ImageInput.open(str(path))
    levels = 0
    while inp.seek_subimage(0, levels):
        levels += 1
    inp.close()
    read = _tiles(path)
    assert levels == 7 and read.mode == OpenEXR.MIPMAP_LEVELS  # 100 wide: floor(log2 100) + 1 levels
    words = f"{read.xSize} x {read.ySize} tiles, mip-mapped, {levels} levels"
    text = _info(path)
    assert [line.strip() for line in text.splitlines() if line.strip().startswith("tiles:")] == [f"tiles: {words}"]
    assert "TileDescription" not in text and "TileDescription" not in _info(path, "--json")
