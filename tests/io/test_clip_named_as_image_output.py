"""A command that writes images (tonemap, compare-tones, diff's error map) given a clip's name (-o out.mp4) says
which commands write clips, instead of claiming that lenslab does not write video (convert and warp do)."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.errors import FormatError
from lenslab.io import write
from lenslab.io.registry import format_for_path, formats

CLIP_EXTENSIONS = sorted(e for f in formats().values() if f.kind == "video" for e in f.extensions)


def test_the_clip_extensions_are_mp4_m4v_mov_mkv():  # the containers of docs/guide/video.md
    assert CLIP_EXTENSIONS == [".m4v", ".mkv", ".mov", ".mp4"]


@pytest.mark.parametrize("ext", CLIP_EXTENSIONS)
def test_a_clip_name_points_to_convert_and_warp(ext):
    with pytest.raises(FormatError) as info:
        format_for_path(f"out{ext}")
    assert "does not write" not in str(info.value)
    assert "'lenslab convert'" in str(info.value) and "'lenslab warp'" in str(info.value)


@pytest.mark.parametrize("command", [["tonemap"], ["compare-tones"], ["diff", "IN"]])
def test_commands_that_write_images_say_it_in_one_usage_line(tmp_path, capsys, command):
    src = tmp_path / "in.exr"
    write(src, np.full((4, 8, 3), 0.5, np.float32))
    out = tmp_path / "out.mp4"
    args = [command[0], str(src), *[str(src) for a in command[1:]], "-o", str(out)]
    assert main(args) == 2
    lines = [line for line in capsys.readouterr().err.splitlines() if line.strip()]
    assert len(lines) == 1 and "a clip is written by 'lenslab convert'" in lines[0], lines
    assert not out.exists()
