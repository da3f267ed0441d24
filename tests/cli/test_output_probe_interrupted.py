"""The check that an output's folder can be written makes a file of the temporaries' pattern and removes it at
once. A Ctrl-C landing between the two steps must not leave that file behind: an interrupted batch leaves no
temporary (``tests/cli/test_signals.py``). Here the signal is sent by the process to itself right after the file
is made, so Python's handler runs exactly between the two steps, every time; the folder is then listed by the
operating system."""

from __future__ import annotations

import os
import signal

import pytest

from lenslab.jobs import policy
from lenslab.jobs.funnel import stop_signals


def test_a_ctrl_c_between_making_and_removing_the_probe_leaves_no_file(tmp_path, monkeypatch):
    real_close = os.close
    sent = []

    def close_then_interrupt(fd):
        real_close(fd)
        if not sent:  # once: the probe's descriptor is the first closed
            sent.append(fd)
            os.kill(os.getpid(), signal.SIGINT)  # handled at the next bytecode: before the probe's removal

    monkeypatch.setattr(os, "close", close_then_interrupt)
    with stop_signals():
        with pytest.raises(KeyboardInterrupt):
            policy.check_writable(tmp_path / "out.exr")
    assert sent and os.listdir(tmp_path) == []
