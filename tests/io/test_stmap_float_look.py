"""``lenslab convert map.exr -o out.exr --exposure 1`` of a map ``lenslab stmap`` marked: refused (exit 2, one line)
as it is for a map written as codes, where it used to double every coordinate and keep the mark, so the map then
read source positions twice as far; without a look the EXR keeps the map's values.

Oracle: OpenEXR's own bindings read the values written."""

from __future__ import annotations

import numpy as np
import OpenEXR
import pytest

from lenslab.cli.main import main


def _rgba(path) -> np.ndarray:
    with OpenEXR.File(str(path)) as f:
        ch = f.channels()
        return np.asarray(ch["RGBA"].pixels, dtype=np.float64) if "RGBA" in ch else \
            np.stack([np.asarray(ch[c].pixels, dtype=np.float64) for c in "RGBA"], -1)


@pytest.mark.parametrize("look, flag", [(["--exposure", "1"], "--exposure"), (["--exposure", "-0.5"], "--exposure")])
@pytest.mark.parametrize("suffix", [".exr", ".hdr"])
def test_a_marked_map_to_floats_given_a_look_is_a_usage_error(tmp_path, capsys, look, flag, suffix):
    """(``--tone`` and ``--display`` into a float file are refused for any image: linear light.)"""
    marked = tmp_path / "map.exr"
    assert main(["stmap", "--from", "fisheye:fov=180", "--to", "perspective:fov=90", "--size", "64x48", "-o",
                 str(marked), "-q"]) == 0
    capsys.readouterr()
    out = tmp_path / f"out{suffix}"
    assert main(["convert", str(marked), "-o", str(out), *look]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"lenslab convert: error: {marked}: is an ST map") and \
        lines[0].endswith(f"never tone-mapped or display-encoded; drop {flag}"), lines
    assert not out.exists()


def test_a_marked_map_to_exr_keeps_its_values(tmp_path):
    marked = tmp_path / "map.exr"
    assert main(["stmap", "--from", "fisheye:fov=180", "--to", "perspective:fov=90", "--size", "64x48", "-o",
                 str(marked), "-q"]) == 0
    out = tmp_path / "copy.exr"
    assert main(["convert", str(marked), "-o", str(out), "--pixel-type", "float", "-q"]) == 0
    assert np.array_equal(_rgba(out), _rgba(marked))
