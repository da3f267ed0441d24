"""An output that already exists is one form in every command: ``PROG: error: OUTPUT: already exists; give
--overwrite to replace it``, naming the output alone (the file the user must move or allow), for one file and
in a batch, for a still image, a clip to a clip and a clip to its frame files; tonemap's form. It is a failed
file (exit status 1: whether it exists is known only from the disk), and the file keeps its bytes. And warp's
summary with ``--stmap`` names the map it warped by, not a count of lens maps it never made."""

from __future__ import annotations

import os

import numpy as np
import pytest

from lenslab.cli.main import main

OLD = b"an earlier output\n"


def _line(command: str, out: str) -> str:
    return f"lenslab {command}: error: {out}: already exists; give --overwrite to replace it"


@pytest.fixture
def stills(tmp_path, monkeypatch):
    from lenslab.io import write

    monkeypatch.chdir(tmp_path)
    rng = np.random.default_rng(5)
    for name in ("a.exr", "b.exr"):
        write(name, rng.uniform(0.0, 2.0, (8, 16, 3)).astype(np.float32))
    return tmp_path


COMMANDS = {"convert": ["--to", "png"], "warp": ["--to", "equirect", "--format", "png"], "tonemap": []}


@pytest.mark.parametrize("command", list(COMMANDS))
def test_one_existing_output_is_named_alone(stills, capsys, command):
    (stills / "old.png").write_bytes(OLD)
    options = {"warp": ["--to", "equirect"], "convert": [], "tonemap": []}[command]  # -o names the format
    code = main([command, "a.exr", *options, "-o", "old.png", "-q"])
    assert code == 1
    assert capsys.readouterr().err.strip().splitlines() == [_line(command, "old.png")]
    assert (stills / "old.png").read_bytes() == OLD


@pytest.mark.parametrize("command", list(COMMANDS))
def test_a_batch_names_each_existing_output_alone(stills, capsys, command):
    (stills / "out").mkdir()
    (stills / "out" / "a.png").write_bytes(OLD)
    code = main([command, "a.exr", "b.exr", *COMMANDS[command], "-o", "out", "-q"])
    assert code == 1
    assert capsys.readouterr().err.strip().splitlines() == [_line(command, os.path.join("out", "a.png"))]
    assert (stills / "out" / "a.png").read_bytes() == OLD and (stills / "out" / "b.png").is_file()


@pytest.fixture
def clip(stills):
    from lenslab.io import write

    for k in range(2):
        write(f"f{k}.png", np.full((16, 32, 3), 0.2 + 0.3 * k, np.float32))
    assert main(["convert", "f0.png", "f1.png", "--to", "mp4", "-o", "clip709.mp4", "-q"]) == 0
    return stills / "clip709.mp4"


@pytest.mark.parametrize("command", [["warp", "--to", "equirect"], ["convert"]])
def test_a_clip_to_an_existing_clip_names_the_output_alone(clip, capsys, command):
    (clip.parent / "f709.mp4").write_bytes(OLD)
    code = main([command[0], "clip709.mp4", *command[1:], "-o", "f709.mp4", "-q"])
    assert code == 1
    assert capsys.readouterr().err.strip().splitlines() == [_line(command[0], "f709.mp4")]
    assert (clip.parent / "f709.mp4").read_bytes() == OLD


@pytest.mark.parametrize("command", [["warp", "--to", "equirect", "--format", "exr"], ["convert", "--to", "exr"]])
def test_a_clip_to_an_existing_frame_file_names_that_frame(clip, capsys, command):
    (clip.parent / "frames").mkdir()
    frame = clip.parent / "frames" / "clip709.000001.exr"
    frame.write_bytes(OLD)
    code = main([command[0], "clip709.mp4", *command[1:], "-o", "frames", "-q"])
    assert code == 1
    assert capsys.readouterr().err.strip().splitlines() == [_line(command[0], os.path.join("frames", frame.name))]
    assert frame.read_bytes() == OLD  # and all or none: frame 0, written before, is not left
    assert sorted(p.name for p in frame.parent.iterdir()) == [frame.name]


def test_warp_by_an_st_map_names_the_map_in_its_summary(stills, capsys):
    from lenslab.io import write

    st = np.zeros((4, 8, 3), np.float32)  # Nuke's STMap: R = x / W, G = 1 - y / H of the source position
    st[..., 0], st[..., 1] = np.meshgrid((np.arange(8) + 0.5) / 8, 1 - (np.arange(4) + 0.5) / 4)
    write("undistort.exr", st)
    code = main(["warp", "a.exr", "b.exr", "--stmap", "undistort.exr", "-o", "out"])
    lines = capsys.readouterr().err.strip().splitlines()
    assert code == 0, lines
    assert lines[-1] == "warped 2 of 2 file(s) by the ST map undistort.exr"
