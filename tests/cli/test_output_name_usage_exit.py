"""An output name whose format lenslab does not write (an unknown extension, or HEIC, which it only reads) is a
usage error in every command that writes images: one line and exit 2 (the brief's code for usage), before
any input is read, and no file written."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import write

COMMANDS = {
    "convert": [],
    "tonemap": [],
    "warp": ["--to", "fisheye:fov=180", "--size", "8x8"],
}


@pytest.mark.parametrize("name", ["out.heic", "out.xyz"])
@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_exit_2_and_one_line(tmp_path, capsys, command, name):
    src = tmp_path / "in.exr"
    write(src, np.ones((8, 16, 3), np.float32))
    out = tmp_path / name
    assert main([command, str(src), "-o", str(out), *COMMANDS[command]]) == 2
    lines = [line for line in capsys.readouterr().err.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith(f"lenslab {command}: error: "), lines
    assert not out.exists()
