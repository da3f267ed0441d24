"""The check that an output's folder can be written makes a file of the temporaries' pattern and removes it at
once. A Ctrl-C landing between the two steps must not leave that file behind: an interrupted batch leaves no
temporary (``tests/cli/test_signals.py``). Here the signal is sent by the process to itself right after the file
is made, so Python's handler runs exactly between the two steps, every time; the folder is then listed by the
operating system."""

from __future__ import annotations

import os
import signal
import threading

import pytest

from lenslab.jobs import policy
from lenslab.jobs.funnel import stop_signals


def _names_a_file_in(fd: int, folder) -> bool:
    """Whether descriptor ``fd`` is open on a file in ``folder`` (as Linux's /proc names it)."""
    try:
        return os.path.dirname(os.readlink(f"/proc/self/fd/{fd}")) == str(folder)
    except OSError:
        return False


def test_a_ctrl_c_between_making_and_removing_the_probe_leaves_no_file(tmp_path, monkeypatch):
    real_close = os.close
    sent = []

    def close_then_interrupt(fd):
        # the probe's descriptor, closed by the main thread: os.close is patched for every thread, and a thread an
        # earlier test left (a decoder, a pool) closing a descriptor of its own must not send the signal instead
        probe = not sent and threading.current_thread() is threading.main_thread() and _names_a_file_in(fd, tmp_path)
        real_close(fd)
        if probe:  # once
            sent.append(fd)
            os.kill(os.getpid(), signal.SIGINT)  # handled at the next bytecode: before the probe's removal

    # Ctrl-C live, as at a terminal: a run started in the background by a shell (`pytest &`) begins with SIGINT
    # ignored, which stop_signals rightly keeps ignored
    saved = signal.signal(signal.SIGINT, signal.default_int_handler)
    monkeypatch.setattr(os, "close", close_then_interrupt)
    try:
        _interrupted_probe(tmp_path)
    finally:
        monkeypatch.undo()
        signal.signal(signal.SIGINT, saved)
    assert sent and os.listdir(tmp_path) == []


def _interrupted_probe(tmp_path) -> None:
    with stop_signals():
        with pytest.raises(KeyboardInterrupt):
            policy.check_writable(tmp_path / "out.exr")
