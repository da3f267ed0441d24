"""lenslab warp's progress bar on a terminal: over the bands the warp draws (every tile's), its total on it from the
first frame drawn and reached at the end; shown once the work lasts the patience (a second), never under -q nor
without a terminal; a step that outlasts the patience is named."""

from __future__ import annotations

import fcntl
import io
import os
import pty
import re
import struct
import subprocess
import sys
import termios
import threading
import time

import numpy as np

from lenslab import io as lio
from lenslab.jobs import progress


def test_the_first_frame_of_the_bar_shows_the_total_bands(tmp_path, monkeypatch):
    """A 1024 x 512 output is warped in bands of 64 rows (65536 samples, at least one band per thread): 8 bands,
    known before the first is done, and the bar ends at 8 of 8."""
    monkeypatch.setenv("LENSLAB_THREADS", "2")
    monkeypatch.setattr(progress, "PATIENCE", 0.0)  # (the bar appears at once: no wait for the work to last)
    lio.write(tmp_path / "p.exr", np.ones((64, 128, 3), np.float32))
    code, out = on_terminal(monkeypatch, ["warp", str(tmp_path / "p.exr"), "-o", str(tmp_path / "o.exr"), "--to",
                                          "equirect", "--size", "1024x512"])
    assert code == 0
    counts = bar_counts(out)
    assert counts[0] == (0, bands(1024, 512)) == (0, 8), out
    assert counts[-1] == (8, 8), out


def on_terminal(monkeypatch, argv) -> tuple[int, str]:
    """``lenslab ARGV`` run here with its stderr on a terminal 120 columns wide (a pseudo-terminal): its exit code
    and what the terminal received."""
    from lenslab.cli.main import main

    master, slave = pty.openpty()
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 40, 120, 0, 0))
    received = []

    def read():
        while True:
            try:
                chunk = os.read(master, 4096)
            except OSError:  # the terminal's other end is closed
                break
            if not chunk:
                break
            received.append(chunk)

    reader = threading.Thread(target=read)
    reader.start()
    stream, stderr = os.fdopen(slave, "w"), sys.stderr
    monkeypatch.setattr(sys, "stderr", stream)
    try:
        code = main(argv)
    finally:
        monkeypatch.setattr(sys, "stderr", stderr)
        stream.close()
        reader.join()
        os.close(master)
    return code, b"".join(received).decode(errors="replace")


def bar_counts(out: str) -> list[tuple[int, int]]:
    """The ``done/total`` of each frame of a bar of bands, in the order drawn."""
    return [(int(n), int(t)) for n, t in re.findall(r"(\d+)/(\d+) \[[^\r]*band", out)]


def bands(width: int, height: int, threads: int = 2) -> int:
    """A single image's bands: rows of 65536 output samples (lenslab.jobs.warp.SCRATCH_POINTS), no more than the
    rows that give each thread one band."""
    rows = min((1 << 16) // width, -(-height // threads))
    return -(-height // rows)


def test_a_tiled_output_counts_each_tile_s_bands(tmp_path, monkeypatch):
    """Each tile of a 2 x 2 grid is warped in its own bands (1024 x 256 pixels: 4 bands), 16 in all: the bar ends at
    16 of 16 (a bar of rows ended at twice the output's rows, each tile's added)."""
    monkeypatch.setenv("LENSLAB_THREADS", "2")
    monkeypatch.setattr(progress, "PATIENCE", 0.0)
    lio.write(tmp_path / "p.exr", np.ones((64, 128, 3), np.float32))
    code, out = on_terminal(monkeypatch, ["warp", str(tmp_path / "p.exr"), "-o", str(tmp_path / "o.exr"), "--to",
                                          "tiled:2x2", "--size", "2048x512"])
    assert code == 0
    counts = bar_counts(out)
    assert counts[0] == (0, 4 * bands(1024, 256)) == (0, 16), out
    assert counts[-1] == (16, 16) and all(n <= t for n, t in counts), out


def test_quiet_prints_nothing_on_a_terminal(tmp_path, monkeypatch):
    monkeypatch.setattr(progress, "PATIENCE", 0.0)
    lio.write(tmp_path / "p.exr", np.ones((64, 128, 3), np.float32))
    assert on_terminal(monkeypatch, ["warp", str(tmp_path / "p.exr"), "-o", str(tmp_path / "o.exr"), "--to",
                                     "equirect", "--size", "1024x512", "-q"]) == (0, "")


def test_work_shorter_than_the_patience_shows_no_bar(tmp_path, monkeypatch):
    """The bar appears once the work has lasted the patience (a second): a patience no warp here reaches leaves
    the terminal the summary line alone."""
    monkeypatch.setattr(progress, "PATIENCE", 1e9)
    lio.write(tmp_path / "p.exr", np.ones((64, 128, 3), np.float32))
    code, out = on_terminal(monkeypatch, ["warp", str(tmp_path / "p.exr"), "-o", str(tmp_path / "o.exr"), "--to",
                                          "equirect", "--size", "1024x512"])
    assert (code, out) == (0, "warped 1 of 1 file(s) with 1 map(s)\r\n")


def test_without_a_terminal_there_is_no_bar(tmp_path):
    """stderr to a pipe (a log, a script): the summary line alone, whatever the work's length."""
    lio.write(tmp_path / "p.exr", np.ones((64, 128, 3), np.float32))
    done = subprocess.run([sys.executable, "-m", "lenslab", "warp", str(tmp_path / "p.exr"), "-o",
                           str(tmp_path / "o.exr"), "--to", "equirect", "--size", "1024x512"],
                          capture_output=True, text=True)
    assert (done.returncode, done.stdout, done.stderr) == (0, "", "warped 1 of 1 file(s) with 1 map(s)\n")


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
