"""lenslab warp's progress bar: its total (the output's rows) is on it from the first frame drawn, and a
step that outlasts the patience is named."""

from __future__ import annotations

import fcntl
import io
import os
import pty
import struct
import subprocess
import sys
import termios
import time

import numpy as np

from lenslab import io as lio
from lenslab.jobs import progress


def test_the_first_frame_of_the_bar_shows_the_total_rows(tmp_path):
    lio.write(tmp_path / "p.exr", np.ones((64, 128, 3), np.float32))
    master, slave = pty.openpty()
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 40, 120, 0, 0))  # a terminal 120 columns wide
    proc = subprocess.Popen([sys.executable, "-m", "lenslab", "warp", str(tmp_path / "p.exr"), "-o",
                             str(tmp_path / "o.exr"), "--to", "fisheye:fov=180", "--size", "96x96"],
                            stdin=slave, stdout=slave, stderr=slave)
    os.close(slave)
    out = b""
    while True:
        try:
            chunk = os.read(master, 4096)
        except OSError:  # the child closed the terminal
            break
        if not chunk:
            break
        out += chunk
    assert proc.wait() == 0
    frames = [f for f in out.decode(errors="replace").split("\r") if "row" in f]
    assert frames, out
    assert "0/96" in frames[0], frames[0]  # 96 output rows, known before the first row is done


def test_a_slow_step_is_named_before_the_bar_appears(monkeypatch):
    monkeypatch.setattr(progress, "PATIENCE", 0.0)
    stream = io.StringIO()
    bar = progress.RowBar("pano.exr", stream)
    bar.status("reading")
    deadline = time.monotonic() + 60.0  # waits for the state (the line written), whatever the load
    while "pano.exr: reading..." not in stream.getvalue() and time.monotonic() < deadline:
        time.sleep(0.01)
    bar.close()
    assert "pano.exr: reading..." in stream.getvalue()


def test_a_step_named_as_the_bar_closes_is_not_shown():
    """The timer that names a slow step can fire as Ctrl-C closes the bar: what it would say must not land
    after the command's interrupted line."""
    stream = io.StringIO()
    bar = progress.RowBar("pano.exr", stream)
    bar.status("reading")
    bar.close()
    bar._say()  # the timer's call, made after the close as a timer that fired just before it makes it
    assert stream.getvalue() == ""
