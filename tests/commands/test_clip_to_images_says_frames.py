"""``lenslab convert clip.mp4 -o out/f.exr`` writes one file per frame (f.000000.exr ...), not the one file the name
says: a note names how many and the first and last names, as they are in the folder (listed by the test)."""

from __future__ import annotations

import os

import numpy as np

from lenslab.cli.main import main
from lenslab.io import write


def test_the_frames_written_are_named(tmp_path, capsys):
    stills = []
    for k in range(3):
        stills.append(tmp_path / f"s{k}.png")
        write(stills[-1], np.full((16, 16, 3), 0.2 * (k + 1), np.float32))
    clip = tmp_path / "clip.mp4"
    assert main(["convert", *map(str, stills), "-o", str(clip), "-q"]) == 0
    out = tmp_path / "out"
    capsys.readouterr()
    assert main(["convert", str(clip), "-o", str(out / "f.exr")]) == 0
    names = sorted(os.listdir(out))
    assert len(names) == 3
    notes = [line for line in capsys.readouterr().err.splitlines() if "frames written" in line]
    assert len(notes) == 1, notes
    assert notes[0].endswith(f"3 frames written: {out / names[0]} to {out / names[-1]}"), notes[0]


def test_a_warped_clip_too(tmp_path, capsys):
    stills = []
    for k in range(2):
        stills.append(tmp_path / f"s{k}.png")
        write(stills[-1], np.full((16, 32, 3), 0.2 * (k + 1), np.float32))
    clip = tmp_path / "clip.mp4"
    assert main(["convert", *map(str, stills), "-o", str(clip), "-q"]) == 0
    out = tmp_path / "out"
    capsys.readouterr()
    assert main(["warp", str(clip), "-o", str(out / "f.exr"), "--to", "fisheye", "--size", "16x16"]) == 0
    names = sorted(os.listdir(out))
    assert len(names) == 2
    notes = [line for line in capsys.readouterr().err.splitlines() if "frames written" in line]
    assert len(notes) == 1 and notes[0].endswith(f"2 frames written: {out / names[0]} to {out / names[-1]}"), notes
