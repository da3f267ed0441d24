"""Side files (camera and calibration files, ``tiles=`` tables, scenes and their ``mtllib``, OCIO
configs, lensfun databases) are opened through :func:`open_side_file` and read through
:func:`read_side_bytes` / :func:`read_side_text`: a regular file (never a device, FIFO, socket or a
``/proc``, ``/sys`` or ``/dev`` path) no larger than its limit, read once and never past the limit.
:func:`check_side_file` gives the same guarantees to a library that opens the file itself (pyvista,
OpenColorIO, lensfun), for the size the file has when checked.

The limit is 64 MiB (``LENSLAB_MAX_SIDE_FILE`` in bytes changes it); a caller may ask for less.
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

from lenslab.errors import InputError
from lenslab.inputs.limits import env_int


#: the largest side file read, in bytes
MAX_SIDE_FILE = env_int("LENSLAB_MAX_SIDE_FILE", 64 << 20)
_PSEUDO = ("/proc", "/sys", "/dev")


def _mib(n: int) -> str:
    return f"{n / (1 << 20):.3g} MiB" if n >= 1 << 20 else f"{n} bytes"


def _refuse_pseudo(path: Path, what: str) -> None:
    try:
        real = os.path.realpath(path)
    except (OSError, ValueError):
        return
    if any(real == p or real.startswith(p + "/") for p in _PSEUDO):
        raise InputError(f"{path}: the {what} is a system path ({real.split('/')[1]}), not a file")


def _check_stat(path: Path, st: os.stat_result, what: str, limit: int) -> None:
    if stat.S_ISDIR(st.st_mode):
        raise InputError(f"{path}: the {what} is a folder, not a file")
    if not stat.S_ISREG(st.st_mode):
        kind = ("a FIFO" if stat.S_ISFIFO(st.st_mode) else "a device" if stat.S_ISCHR(st.st_mode)
                or stat.S_ISBLK(st.st_mode) else "a socket" if stat.S_ISSOCK(st.st_mode) else "not a regular file")
        raise InputError(f"{path}: the {what} is {kind}; give a regular file")
    if st.st_size > limit:
        raise InputError(f"{path}: the {what} holds {_mib(st.st_size)}, more than the {_mib(limit)} a {what} "
                         "may hold (LENSLAB_MAX_SIDE_FILE raises the limit)")


def check_side_file(path, what: str = "side file", limit: int | None = None) -> Path:
    """``path`` as a Path when it is a regular file within ``limit`` bytes; InputError (one line) else,
    FileNotFoundError when it does not exist."""
    path = Path(path)
    limit = MAX_SIDE_FILE if limit is None else limit
    _refuse_pseudo(path, what)
    try:
        st = os.stat(path)
    except FileNotFoundError:
        raise FileNotFoundError(f"{path}: no such {what}") from None
    except OSError as exc:
        raise InputError(f"{path}: the {what} cannot be read ({exc.strerror or exc})") from None
    _check_stat(path, st, what, limit)
    return path


def read_side_bytes(path, what: str = "side file", limit: int | None = None) -> bytes:
    """The bytes of a side file, checked as :func:`check_side_file` says; never reads past ``limit``."""
    path = Path(path)
    limit = MAX_SIDE_FILE if limit is None else limit
    _refuse_pseudo(path, what)
    try:  # O_NONBLOCK: opening a FIFO must not wait for a writer
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0))
    except FileNotFoundError:
        raise FileNotFoundError(f"{path}: no such {what}") from None
    except IsADirectoryError:
        raise InputError(f"{path}: the {what} is a folder, not a file") from None
    except OSError as exc:
        raise InputError(f"{path}: the {what} cannot be read ({exc.strerror or exc})") from None
    try:
        _check_stat(path, os.fstat(fd), what, limit)
        chunks, got = [], 0
        while got <= limit:
            block = os.read(fd, min(1 << 20, limit + 1 - got))
            if not block:
                break
            chunks.append(block)
            got += len(block)
        if got > limit:  # it grew while being read
            raise InputError(f"{path}: the {what} holds more than {_mib(limit)}")
        return b"".join(chunks)
    finally:
        os.close(fd)


def read_side_text(path, what: str = "side file", limit: int | None = None) -> str:
    """The UTF-8 text of a side file (see :func:`read_side_bytes`); InputError if it is not text."""
    data = read_side_bytes(path, what, limit)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise InputError(f"{path}: the {what} is not UTF-8 text (byte {exc.start})") from None
