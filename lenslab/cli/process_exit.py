"""The end of the ``lenslab`` process, without the interpreter's teardown.

Once a command has returned, every output it wrote is closed and renamed into place (outputs are written to a
temporary name, then renamed: :mod:`lenslab.atomic`). What Python's own exit then does (``Py_FinalizeEx``) costs
18 to 31 ms of CPU for a video warp: it clears every module, runs the cycle collector over all of them and frees
NumPy's, PyAV's and the kernels' objects one by one, work whose result the operating system throws away.
:func:`exit_now` does the part of that exit whose effects outlive the process, in the interpreter's order, then
ends the process:

1. non-daemon threads are joined (``threading._shutdown``, which also stops ``concurrent.futures`` pools);
2. the ``atexit`` handlers run (a library's log files, coverage data, temporary directories);
3. Python's standard output and error are flushed, then C's stdio buffers (``fflush(NULL)``: what C libraries
   printed through ``printf``);
4. ``os._exit(code)``.

If a flush fails (standard output was a pipe whose reader went away), the interpreter's exit runs after all, as
before: its exit code and its message on standard error stay what they were. Only the console command calls this
(``lenslab`` and ``python -m lenslab``); :func:`lenslab.cli.main.main` called from Python returns as it always did.
"""

from __future__ import annotations

import os
import sys


def _flush_c_stdio() -> None:
    """``fflush(NULL)``: C's buffered standard output of the libraries the command loaded."""
    try:
        import ctypes

        ctypes.CDLL(None).fflush(None)
    except (ImportError, OSError, AttributeError):  # no C library to ask: nothing buffered there to lose
        pass


def exit_now(code: int) -> None:
    """End the process with ``code`` after joining threads, running ``atexit`` and flushing standard streams;
    raise ``SystemExit(code)`` (the interpreter's usual exit) where a standard stream cannot be flushed."""
    import atexit
    import threading

    threading._shutdown()  # what Py_FinalizeEx does first: wait for non-daemon threads
    atexit._run_exitfuncs()
    atexit._clear()  # run once: the interpreter's exit, if it still comes, finds none
    try:
        for stream in (sys.stdout, sys.stderr, sys.__stdout__, sys.__stderr__):
            if stream is not None:
                stream.flush()
    except (OSError, ValueError):
        raise SystemExit(code) from None
    _flush_c_stdio()
    os._exit(code & 0xFF)


__all__ = ["exit_now"]
