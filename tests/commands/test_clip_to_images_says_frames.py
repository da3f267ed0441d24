"""``lenslab convert clip.mp4 -o out/f.exr`` (and ``warp`` alike) writes one file per frame (f.000000.exr ...), not the
one file the name says: a note names how many and the first and last names, as they are in the folder (listed by
the test)."""

from __future__ import annotations

import os

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import write


def _clip(tmp_path, frames: int):
    stills = []
    for k in range(frames):
        stills.append(tmp_path / f"s{k}.png")
        write(stills[-1], np.full((16, 32, 3), 0.2 * (k + 1), np.float32))
    clip = tmp_path / "clip.mp4"
    assert main(["convert", *map(str, stills), "-o", str(clip), "-q"]) == 0
    return clip


@pytest.mark.parametrize("command, extra", [("convert", []), ("warp", ["--to", "fisheye", "--size", "16x16"])])
def test_the_frames_written_are_named(tmp_path, capsys, command, extra):
    clip = _clip(tmp_path, 3)
    out = tmp_path / "out"
    capsys.readouterr()
    assert main([command, str(clip), "-o", str(out / "f.exr"), *extra]) == 0
    names = sorted(os.listdir(out))
    assert len(names) == 3
    notes = [line for line in capsys.readouterr().err.splitlines() if "frames written" in line]
    assert len(notes) == 1, notes
    assert notes[0].endswith(f"3 frames written: {out / names[0]} to {out / names[-1]}"), notes[0]
