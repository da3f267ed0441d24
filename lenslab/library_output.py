"""Keep what a C library prints about a damaged file off the terminal.

OpenEXR's C core reports a damaged chunk on standard error (``FILE: (EXR_ERR_CORRUPT_CHUNK) ...``, one
line per failed step) and its Python bindings add ``Warning: Exception raised reading pixel data ...`` on
standard output, below Python's ``sys.stderr``/``sys.stdout``: a failed input would show several lines
besides lenslab's own ``lenslab CMD: error: FILE: cause``. :func:`quiet_library` points file descriptors
1 and 2 at temporary files for the duration of a library call, then gives back to the real descriptors
every captured line that is not the library's (lenslab's own notes, a progress bar from another thread),
and hands the library's lines to the caller, which may use the first as the cause in its one-line error.

Stop signals: the redirection is made and undone whole (:func:`quiet_library`).

Threads: the redirection is process-wide, so one library call holds it at a time (a reentrant lock held
for the whole block: a thread may nest calls, other threads wait to start theirs). Output another thread
writes meanwhile is captured too and given back as soon as the call ends, in order per stream; the
library's lines handed back are then only this call's, so a damaged file gets the same cause alone and in
a batch of threads. OpenEXR decodes on its own thread pool, so one read at a time still uses every core.
"""

from __future__ import annotations

import contextlib
import os
import re
import sys
import tempfile
import threading

from lenslab.errors import stop_signals_held

#: lines OpenEXR prints: its C core's error handler and its Python bindings' reading warning
LIBRARY_LINE = re.compile(r"\((EXR_ERR_\w+)\)|^Warning: Exception raised (reading|writing)")

_lock = threading.RLock()  # held for a whole capture: one thread's library calls at a time
_state: dict = {"depth": 0, "saved": None}


def _flush() -> None:
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(Exception):
            stream.flush()


def _begin() -> None:
    _flush()
    saved = []
    try:
        for fd in (1, 2):
            spool = tempfile.TemporaryFile()
            saved.append((fd, os.dup(fd), spool))
            os.dup2(spool.fileno(), fd)
    except OSError:  # a closed descriptor: nothing to protect
        for fd, old, spool in saved:
            os.dup2(old, fd)
            os.close(old)
            spool.close()
        saved = None
    _state["saved"] = saved


def _library_lines(text: str) -> list[str]:
    return [line.strip() for line in text.splitlines() if LIBRARY_LINE.search(line)]


def _so_far() -> list[str]:
    """The library's lines captured until now (the capture goes on for the other threads inside)."""
    _flush()
    lines: list[str] = []
    for _fd, _old, spool in _state["saved"] or ():
        with contextlib.suppress(OSError):
            size = os.fstat(spool.fileno()).st_size
            lines += _library_lines(os.pread(spool.fileno(), size, 0).decode("utf-8", "replace"))
    return lines


def _end() -> list[str]:
    _flush()
    saved, _state["saved"] = _state["saved"], None
    said: list[str] = []
    for fd, old, spool in saved or ():
        try:
            os.dup2(old, fd)  # each descriptor back first, whatever happens to the others
        finally:
            os.close(old)
        try:
            spool.seek(0)
            text = spool.read().decode("utf-8", "replace")
        finally:
            spool.close()
        keep = []
        for line in text.splitlines(keepends=True):
            (said if LIBRARY_LINE.search(line) else keep).append(line)
        if keep:
            with contextlib.suppress(OSError):
                os.write(fd, "".join(keep).encode())
    return [line.strip() for line in said]


@contextlib.contextmanager
def quiet_library(said: list[str] | None = None):
    """Run the block with the library's own lines kept off standard output and error; append them (stripped)
    to ``said`` when given (the outermost call of a thread's nested ones gets them all).

    A stop signal (Ctrl-C, SIGTERM) received inside is raised once the descriptors are given back
    (:func:`~lenslab.errors.stop_signals_held`): raised between two of their steps, it would leave standard
    error pointed at a temporary file, and the command's last line, ``interrupted``, would go there. The block
    is one call of the library, which a signal's handler cannot interrupt anyway."""
    with _lock, stop_signals_held():
        if _state["depth"] == 0:
            _begin()
        _state["depth"] += 1
        try:
            yield
        finally:
            _state["depth"] -= 1
            lines = _end() if _state["depth"] == 0 else _so_far()
            if said is not None:
                said.extend(lines)


def library_call(path, call, cannot: str, consequence: str = "the file is damaged", library_errors=(Exception,)):
    """``call()`` with the library's own lines kept off the terminal (:func:`quiet_library`); a failure becomes
    one :class:`~lenslab.errors.FormatError`: ``PATH: CANNOT (cause); CONSEQUENCE``, the cause the library's
    first line about ``path`` (:func:`failure_cause`)."""
    from lenslab.errors import FormatError

    said: list[str] = []
    try:
        with quiet_library(said):
            return call()
    except Exception as exc:  # the library's own words where it gives any, not an error of its bindings
        why = failure_cause(said, exc, path, library_errors)
        why = f" ({why})" if why else ""
        raise FormatError(f"{path}: {cannot}{why}; {consequence}") from None


def library_cause(said: list[str], path) -> str:
    """The first captured line about ``path`` (a line that names another file is another thread's), without
    the path, as a cause for an error message ('' if none)."""
    prefix = f"{path}: "
    for line in said:
        m = LIBRARY_LINE.search(line)
        if m and m.group(1) and (line.startswith(prefix) or line.startswith(m.group(0))):
            text = line[len(prefix):] if line.startswith(prefix) else line
            return f"{m.group(1)}: {text.replace(m.group(0), '', 1).strip()}"
    return ""


def failure_cause(said: list[str], exc: BaseException, path, library_errors=(Exception,)) -> str:
    """Why OpenEXR failed on ``path``, in whole words: the first line the library printed about it, else
    the exception's first line when it is one of ``library_errors`` (the bindings' own errors, such as an
    IndexError of a failed read, say nothing), the file's name left out (the message names it)."""
    from lenslab.errors import cause

    why = library_cause(said, path) or (cause(exc, 400) if isinstance(exc, library_errors) else "")
    why = why.replace(f" in {path},", ",").replace(f" in {path}", "").replace(str(path), "the file")
    return cause(why, 100) if why else ""
