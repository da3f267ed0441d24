"""An output whose folder takes no new file (``/proc``, where the kernel itself refuses to create one) is
refused before any input is read: exit 1, one line naming the output as typed, never the hidden temporary
and never the input."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

import lenslab
from lenslab.cli.main import main


def _kernel_refuses(folder: str) -> bool:
    """Whether the operating system refuses to create a file in ``folder`` (asked directly, not through lenslab)."""
    probe = os.path.join(folder, f".lenslab-test-{os.getpid()}")
    try:
        os.close(os.open(probe, os.O_WRONLY | os.O_CREAT | os.O_EXCL))
    except OSError:
        return True
    os.unlink(probe)
    return False


@pytest.mark.parametrize("command", [["convert"], ["warp", "--to", "fisheye:fov=180"]])
def test_an_unwritable_folder_is_refused_before_the_input_is_read(tmp_path, monkeypatch, capsys, command):
    if not Path("/proc").is_dir() or not _kernel_refuses("/proc"):
        pytest.skip("needs a /proc where no file can be made (Linux)")
    src = lenslab.write(tmp_path / "pano.exr", np.full((8, 16, 3), 0.5, np.float32))
    import lenslab.io as lio

    def unread(*args, **kwargs):
        raise AssertionError("the input was read")

    monkeypatch.setattr(lio, "read", unread)
    out = "/proc/p.png" if command[0] == "convert" else "/proc/p.exr"
    assert main([command[0], str(src), "-o", out, *command[1:]]) == 1
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1, lines
    assert lines[0].startswith(f"lenslab {command[0]}: error: {out}: cannot be written"), lines
    assert ".tmp-" not in lines[0] and "pano.exr" not in lines[0] and "was read" not in lines[0]
