"""A stop signal that lands while OpenEXR's lines are being kept off the terminal (standard error pointed at a
temporary file for one library call, :func:`lenslab.library_output.quiet_library`) still ends the command with
its one line on the real standard error: the signal's exception waits until the descriptors are given back.

The child sends SIGTERM to itself from inside the capture's own ``os.dup2`` calls, at the two steps where an
exception would leave descriptor 2 pointed away: just after it was pointed at the temporary file, and just
before it is given back. A signal sent by a process to itself is delivered before ``kill`` returns (POSIX), and
CPython runs the handler as soon as the call returns, so each lands at that exact step: a state, not a timing.
Where descriptor 2 points is the kernel's answer (``fstat``: device and inode), compared with the stream the
child started with.
"""

from __future__ import annotations

import subprocess
import sys
import textwrap

import pytest

from tests.child_signals import default_stop_signals

HANG_GUARD = 120  # seconds: only against a child that would otherwise wait forever on a broken build

CHILD = textwrap.dedent('''
    import os
    import signal
    import sys

    from lenslab.jobs.funnel import Interrupted, stop_signals
    from lenslab.library_output import quiet_library

    step = sys.argv[1]
    identity = lambda fd: (os.fstat(fd).st_dev, os.fstat(fd).st_ino)
    stderr = identity(2)
    real_dup2 = os.dup2

    def dup2(fd, fd2, *args, **kwargs):
        away = fd2 == 2 and identity(fd) != stderr  # pointing descriptor 2 at the capture's file
        back = fd2 == 2 and identity(fd) == stderr  # giving descriptor 2 back
        if back and step == "giving back":
            os.kill(os.getpid(), signal.SIGTERM)
        result = real_dup2(fd, fd2, *args, **kwargs)
        if away and step == "pointing away":
            os.kill(os.getpid(), signal.SIGTERM)
        return result

    os.dup2 = dup2
    try:
        with stop_signals():
            with quiet_library():
                print("the call ran", file=sys.stderr)
            print("not interrupted")
    except Interrupted as exc:
        print(exc.signum)
    print(identity(2) == stderr)
''')


@pytest.mark.parametrize("step", ["pointing away", "giving back"])
def test_a_stop_signal_inside_a_capture_leaves_standard_error_where_it_was(step):
    proc = subprocess.run([sys.executable, "-c", CHILD, step], capture_output=True, text=True, timeout=HANG_GUARD,
                          preexec_fn=default_stop_signals)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split() == ["15", "True"], proc.stdout + proc.stderr  # SIGTERM's number (POSIX)
    assert "Traceback" not in proc.stderr


HELD = textwrap.dedent('''
    import os
    import signal

    from lenslab.errors import stop_signals_held
    from lenslab.jobs.funnel import Interrupted, stop_signals

    try:
        with stop_signals():
            with stop_signals_held():
                with stop_signals_held():
                    os.kill(os.getpid(), signal.SIGTERM)
                    os.kill(os.getpid(), signal.SIGHUP)
                    print("inner")
                print("outer")
            print("not interrupted")
    except Interrupted as exc:
        print(exc.signum)
''')


def test_a_held_stop_is_raised_once_when_the_outermost_block_ends():
    proc = subprocess.run([sys.executable, "-c", HELD], capture_output=True, text=True, timeout=HANG_GUARD,
                          preexec_fn=default_stop_signals)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split() == ["inner", "outer", "15"], proc.stdout + proc.stderr  # the first stop: SIGTERM
