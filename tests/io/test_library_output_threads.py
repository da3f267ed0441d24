"""One capture of the terminal at a time: while a thread is inside :func:`quiet_library` (OpenEXR's lines
kept off standard error) no other thread's capture can start, so each call's captured lines are its own,
and what another thread writes meanwhile reaches the real stream once the call ends. States, not timings:
the lock is probed without blocking from another thread."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
import threading

from lenslab import library_output
from lenslab.library_output import quiet_library


def test_a_second_thread_cannot_start_a_capture_while_one_is_open():
    inside, leave = threading.Event(), threading.Event()
    seen = {}

    def holder():
        with quiet_library():
            inside.set()
            leave.wait()

    t = threading.Thread(target=holder)
    t.start()
    inside.wait()

    def probe():
        got = library_output._lock.acquire(blocking=False)
        seen["free"] = got
        if got:
            library_output._lock.release()

    p = threading.Thread(target=probe)
    p.start()
    p.join()
    leave.set()
    t.join()
    assert seen["free"] is False
    assert library_output._state["depth"] == 0 and library_output._state["saved"] is None


def test_another_threads_line_comes_out_after_the_call_and_the_librarys_line_does_not():
    code = textwrap.dedent("""
        import os, threading
        from lenslab.library_output import quiet_library
        said = []
        with quiet_library(said):
            os.write(2, b"x.exr: (EXR_ERR_CORRUPT_CHUNK) bad chunk\\n")
            t = threading.Thread(target=lambda: os.write(2, b"progress 50%\\n"))
            t.start(); t.join()
        os.write(2, ("said=" + repr(said) + "\\n").encode())
    """)
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)})
    assert run.returncode == 0, run.stderr
    lines = run.stderr.splitlines()
    assert lines[0] == "progress 50%"
    assert lines[1] == "said=['x.exr: (EXR_ERR_CORRUPT_CHUNK) bad chunk']"
    assert len(lines) == 2
