"""A single ``lenslab convert`` on a terminal names each step that outlasts the patience (reading, converting, then
writing NAME: encoding an 8000 x 8000 PNG takes seconds), instead of a "reading..." that stays the last word while
the tone curve and the encoder run. Read from what a pseudo-terminal received."""

from __future__ import annotations

import threading

import numpy as np

import lenslab.io as lio
from lenslab.jobs import progress
from tests.warp.test_warp_progress import on_terminal

HANG_GUARD = 60.0  # seconds: only a hung machine takes this long for a timer of no delay to fire


def test_a_slow_write_is_named(tmp_path, monkeypatch):
    monkeypatch.setattr(progress, "PATIENCE", 0.0)
    lio.write(tmp_path / "p.exr", np.full((16, 32, 3), 0.5, np.float32))
    said = threading.Event()
    say = progress.RowBar._say

    def _say(self):
        say(self)
        if self.step.startswith("writing"):
            said.set()

    monkeypatch.setattr(progress.RowBar, "_say", _say)
    write = lio.write

    def held(path, *args, **kwargs):  # the writer waits until the step is said, as a large file's would last
        if str(path).endswith("o.png"):
            assert said.wait(HANG_GUARD)
        return write(path, *args, **kwargs)

    monkeypatch.setattr(lio, "write", held)
    code, out = on_terminal(monkeypatch, ["convert", str(tmp_path / "p.exr"), "-o", str(tmp_path / "o.png")])
    assert code == 0
    assert "p.exr: writing o.png..." in out, out
    assert out.index("p.exr: writing o.png...") < out.index("converted 1 of 1 file(s) to PNG")


def test_a_single_tonemap_names_its_slow_steps(tmp_path, monkeypatch):
    """``lenslab tonemap`` of one image said nothing at all until its summary (43 s for an 8000 x 8000 EXR to PNG on
    a loaded machine): it names the reading, then the tone mapping and writing, each once it outlasts the patience."""
    monkeypatch.setattr(progress, "PATIENCE", 0.0)
    lio.write(tmp_path / "p.exr", np.full((16, 32, 3), 0.5, np.float32))
    said = threading.Event()
    say = progress.RowBar._say

    def _say(self):
        say(self)
        if self.step.startswith("tone-mapping"):
            said.set()

    monkeypatch.setattr(progress.RowBar, "_say", _say)
    write = lio.write

    def held(path, *args, **kwargs):
        if str(path).endswith("o.png"):
            assert said.wait(HANG_GUARD)
        return write(path, *args, **kwargs)

    monkeypatch.setattr(lio, "write", held)
    code, out = on_terminal(monkeypatch, ["tonemap", str(tmp_path / "p.exr"), "-o", str(tmp_path / "o.png")])
    assert code == 0
    assert "p.exr: tone-mapping and writing o.png..." in out, out
    assert out.index("tone-mapping and writing o.png...") < out.index("o.png: 32 x 16, curve")
