"""EXR to EXR writes scanlines: a tiled input's tiles, and a mip-mapped input's smaller levels, are not
kept, and convert says so in one note line. Expected values: the tile size in OpenEXR's reading of the
input's header, the level count OpenImageIO finds (its MIP levels), the storage of the output in
OpenEXR's reading of it."""

from __future__ import annotations

import subprocess
import sys
import warnings

import numpy as np
import OpenEXR
import pytest

from lenslab.io.exr.keep import ScanlineWarning
from lenslab.jobs.convert import ConvertJob

oiio = pytest.importorskip("OpenImageIO")


def _tiled(path):
    rgb = np.random.default_rng(2).uniform(0, 4, (50, 70, 3)).astype(np.float16)
    tiles = OpenEXR.TileDescription()
    tiles.xSize, tiles.ySize, tiles.mode = 32, 16, OpenEXR.ONE_LEVEL
    OpenEXR.File({"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.tiledimage, "tiles": tiles},
                 {"RGB": rgb}).write(str(path))
    return path


def _mipmapped(path):
    buf = oiio.ImageBuf(oiio.ImageSpec(100, 60, 3, "half"))
    oiio.ImageBufAlgo.fill(buf, (0.5, 0.2, 0.1))
    assert oiio.ImageBufAlgo.make_texture(oiio.MakeTxTexture, buf, str(path), oiio.ImageSpec()), oiio.geterror()
    return path


def _notes(src, out):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ConvertJob(to="exr").run(str(src), str(out))
    return [w.message.command_line for w in caught if issubclass(w.category, ScanlineWarning)]


def _levels(path) -> int:
    inp = oiio.ImageInput.open(str(path))
    n = 0
    while inp.seek_subimage(0, n):
        n += 1
    inp.close()
    return n


def test_a_tiled_file_is_said_to_be_written_as_scanlines(tmp_path):
    src = _tiled(tmp_path / "tiled.exr")
    tiles = OpenEXR.File(str(src), header_only=True).parts[0].header["tiles"]
    out = tmp_path / "out.exr"
    assert _notes(src, out) == [f"tiled ({tiles.xSize} x {tiles.ySize} tiles): written as scanlines"]
    written = OpenEXR.File(str(out), header_only=True).parts[0].header
    assert written["type"] == OpenEXR.scanlineimage and "tiles" not in written
    np.testing.assert_array_equal(OpenEXR.File(str(out)).parts[0].channels["RGB"].pixels,
                                  OpenEXR.File(str(src)).parts[0].channels["RGB"].pixels)


def test_a_mipmapped_file_names_the_levels_left_out(tmp_path):
    src = _mipmapped(tmp_path / "mip.exr")
    levels = _levels(src)
    tiles = OpenEXR.File(str(src), header_only=True).parts[0].header["tiles"]
    assert levels > 1 and tiles.mode == OpenEXR.MIPMAP_LEVELS
    assert _notes(src, tmp_path / "out.exr") == [
        f"tiled ({tiles.xSize} x {tiles.ySize} tiles, mip-mapped, {levels} levels): written as scanlines, the "
        f"full-resolution level only (the {levels - 1} smaller levels are not written)"]


def test_a_scanline_file_gets_no_note(tmp_path):
    import lenslab.io as lio

    src = tmp_path / "s.exr"
    lio.write(src, np.ones((4, 5, 3), np.float32))
    assert _notes(src, tmp_path / "out.exr") == []


def test_the_command_prints_one_note_line(tmp_path):
    src = _tiled(tmp_path / "tiled.exr")
    run = subprocess.run([sys.executable, "-m", "lenslab", "convert", str(src), "--to", "exr", "-o",
                          str(tmp_path / "out.exr")], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    notes = [line for line in run.stderr.splitlines() if "note:" in line]
    assert notes == [f"lenslab convert: note: {src}: tiled (32 x 16 tiles): written as scanlines"]
