"""A clip written as one image per frame (``-o NAME.exr``: ``NAME.000000.exr`` ...) to a name that fits 255 bytes
but whose frames' names do not: one line that shows the frame's number in the name it cannot write (the name as
given, shortened alone, would read as if the name given were too long), and nothing written.

Oracle: the kernel refuses a name of that many bytes (ENAMETOOLONG), counted here from the name in UTF-8."""

from __future__ import annotations

import errno
import os

import pytest

from lenslab.cli.main import main
from tests.warp.test_video_warp_imports import _clip


@pytest.mark.parametrize("command", ["convert", "warp"])
def test_frames_whose_names_pass_255_bytes_are_named_in_one_line(tmp_path, capsys, command):
    _clip(tmp_path / "clip.mp4")
    out = tmp_path / ("é" * 122 + "ab.exr")  # 250 bytes: a name the file system takes
    assert len(out.name.encode()) == 250
    frame = tmp_path / (out.stem + ".000000.exr")  # FFmpeg's and lenslab's frame numbering: 6 digits from 0
    with pytest.raises(OSError) as kernel:
        os.close(os.open(frame, os.O_WRONLY | os.O_CREAT, 0o600))
    assert kernel.value.errno == errno.ENAMETOOLONG
    args = [command, str(tmp_path / "clip.mp4"), "-o", str(out)] + \
        (["--from", "equirect", "--to", "fisheye:fov=180", "--size", "32x32"] if command == "warp" else [])
    assert main(args) == 1
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1, lines
    assert "ab.000000.exr: its name is too long: 257 bytes, where a file name holds at most 255" in lines[0], lines
    assert sorted(os.listdir(tmp_path)) == ["clip.mp4"]
