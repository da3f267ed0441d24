"""Children of the signal tests start with the default handling of the stop signals, as from a terminal.

A test runner started under ``nohup`` or in the background of a non-interactive shell ignores SIGHUP or
SIGINT, and a child inherits that (POSIX keeps ignored signals across exec); lenslab then rightly keeps
ignoring them, and a test that sends them would wait for nothing. The tests are about lenslab's own
handling, so they start it as a terminal would.
"""

from __future__ import annotations

import signal


def default_stop_signals() -> None:
    """``preexec_fn``: SIGHUP, SIGINT and SIGTERM back to their default handling in the child."""
    for sig in (signal.SIGHUP, signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, signal.SIG_DFL)
