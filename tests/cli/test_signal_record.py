"""The record of a stop signal lasts as long as the handlers that made it: once ``stop_signals`` has given the
signals back, a later error of the library (in a notebook, or the next file of a program's own loop) is that
error again, never an interrupt. The interrupt ends the block as ``Interrupted`` with SIGTERM's number (15,
POSIX), and the library then reports a RuntimeError of its own as no signal (None).

The child starts with the default handling of the stop signals (as from a terminal) and sends SIGTERM to
itself; it waits for the handler's exception (a state), not for a duration.
"""

from __future__ import annotations

import subprocess
import sys
import textwrap

from tests.child_signals import default_stop_signals

HANG_GUARD = 120  # seconds: only against a child that would otherwise wait forever on a broken build

CHILD = textwrap.dedent('''
    import os
    import signal
    import threading

    from lenslab.errors import stop_signal
    from lenslab.jobs.funnel import Interrupted, stop_signals

    try:
        with stop_signals():
            os.kill(os.getpid(), signal.SIGTERM)
            threading.Event().wait(120)  # the handler raises in here
        print("not interrupted")
    except Interrupted as exc:
        print(exc.signum)
    print(stop_signal(RuntimeError("a later error of the library")))
    print(signal.getsignal(signal.SIGTERM) is signal.SIG_DFL)
''')


def test_a_signal_is_forgotten_once_the_handlers_are_given_back():
    proc = subprocess.run([sys.executable, "-c", CHILD], capture_output=True, text=True, timeout=HANG_GUARD,
                          preexec_fn=default_stop_signals)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split() == ["15", "None", "True"], proc.stdout + proc.stderr
