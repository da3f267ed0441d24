"""Ctrl-C at any moment of a render leaves the interrupted line last on the terminal.

A render's bands run on pool threads; if they drew the progress bar, one still tracing when Ctrl-C closed
the bar (a thread whose start the interrupt cut short is not joined by the pool) redrew it after the
command's last line. The bar is drawn by the thread that called ``render`` only. And a bar the interrupt
caught half-built is no error of its own: the command still ends as interrupted.
"""

from __future__ import annotations

import io
import sys
import threading

from lenslab.lenses import Camera, make_lens


class _Terminal(io.StringIO):
    """Standard error on a terminal (bars are drawn on one only); notes which thread wrote each piece."""

    def __init__(self):
        super().__init__()
        self.writers: set[str] = set()

    def isatty(self) -> bool:
        return True

    def write(self, s: str) -> int:
        self.writers.add(threading.current_thread().name)
        return super().write(s)


def test_the_progress_bar_is_drawn_by_the_rendering_thread_only(monkeypatch):
    import tqdm

    from tracer.rendering import render

    class EveryUpdate(tqdm.tqdm):  # no rate limit: every band's update would draw, whoever makes it
        def __init__(self, *args, **kwargs):
            super().__init__(*args, **{**kwargs, "mininterval": 0, "miniters": 1})

    term = _Terminal()
    monkeypatch.setattr(tqdm, "tqdm", EveryUpdate)
    monkeypatch.setattr(sys, "stderr", term)
    camera = Camera(make_lens("perspective:fov=60", (32, 32)), {})
    result = render("cornell", camera, spp=2, seed=0, threads=2, batch=64, progress=True)
    assert result.spp == 2
    assert "tracing cornell" in term.getvalue()  # the bar was drawn
    assert "2.05k/2.05k" in term.getvalue()  # and moved to its end (32 x 32 pixels x 2 samples)
    assert term.writers == {threading.current_thread().name}


def test_a_bar_the_interrupt_caught_half_built_is_dropped(monkeypatch):
    from tqdm import tqdm

    from tracer.cli import _close_bars

    term = _Terminal()
    monkeypatch.setattr(sys, "stderr", term)
    # what Ctrl-C inside tqdm(...) leaves between the bar's registration and its position (tqdm 4.70's
    # __init__ sets ``disable`` and then ``pos``): registered, not closable
    half = tqdm.__new__(tqdm)
    half.disable = False
    try:
        _close_bars()  # no AttributeError in place of the interrupt
        assert half not in tqdm._instances
        assert term.getvalue() == "\r\033[K"  # the terminal's line is cleared all the same
    finally:
        tqdm._instances.discard(half)
        half.disable = True  # nothing for its finaliser to close
