"""Once the bar of a single warp or ST map is full, the output is still to be written (an 8000 x 8000 EXR: seconds
of conversion and compression): the full bar names that step, ``writing NAME``, should it outlast the patience,
instead of sitting at 100% without a word. Read from what a pseudo-terminal received."""

from __future__ import annotations

import threading

import numpy as np

from lenslab import io as lio
from lenslab.jobs import progress
from tests.warp.test_warp_progress import on_terminal

HANG_GUARD = 60.0  # seconds: only a hung machine takes this long for a timer of no delay to fire


def _held_until_said(monkeypatch, module, name, step="", output=""):
    """Make ``module.name`` (the writer) wait until the bar's timer has said the step under way (one beginning with
    ``step``): the test then reads the terminal in the state the user sees while a large file is written, whatever
    the machine's load. ``output``: only a write to a path ending so waits."""
    said = threading.Event()
    say = progress.RowBar._say

    def _say(self):
        say(self)
        if self.step.startswith(step):
            said.set()

    monkeypatch.setattr(progress.RowBar, "_say", _say)
    write = getattr(module, name)

    def held(*args, **kwargs):
        if str(args[0] if args else "").endswith(output):
            assert said.wait(HANG_GUARD)
        return write(*args, **kwargs)

    monkeypatch.setattr(module, name, held)


def test_a_full_warp_bar_names_the_writing(tmp_path, monkeypatch):
    import lenslab.jobs.warp.output as warp_output

    monkeypatch.setattr(progress, "PATIENCE", 0.0)
    lio.write(tmp_path / "p.exr", np.ones((64, 128, 3), np.float32))
    _held_until_said(monkeypatch, warp_output, "write_warped")
    code, out = on_terminal(monkeypatch, ["warp", str(tmp_path / "p.exr"), "-o", str(tmp_path / "o.exr"), "--to",
                                          "equirect", "--size", "256x128"])
    assert code == 0
    assert "writing o.exr]" in out, out
    assert (tmp_path / "o.exr").exists()


def test_a_full_st_map_bar_names_the_writing(tmp_path, monkeypatch):
    import lenslab.stmap as stmap

    monkeypatch.setattr(progress, "PATIENCE", 0.0)
    _held_until_said(monkeypatch, stmap, "write_st_map")
    code, out = on_terminal(monkeypatch, ["stmap", "--from", "fisheye:fov=180", "--to", "equirect", "--size",
                                          "256x128", "-o", str(tmp_path / "st.exr")])
    assert code == 0
    assert "writing st.exr]" in out, out
    assert "256/256" not in out and "128/128 [" in out, out  # a bar of the map's rows, ended at its total
