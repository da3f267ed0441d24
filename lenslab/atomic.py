"""Atomic output: every file is written to a temporary name in the target's directory, then renamed.

A reader never sees a half-written file, and a failure (an exception, a full disk, Ctrl-C, SIGTERM)
leaves nothing behind but what was there before. A temporary is named for the process that owns it
(``.STEM.tmp-PID-HOST-RANDOM.SUFFIX``, the stem shortened where the name would pass 255 bytes, see
:func:`temporary_parts`): one left by a process that died (SIGKILL, a lost machine) is
found by :func:`lenslab.staging.sweep` once that process is gone. Only regular files are ever replaced:
a FIFO or a device node in an output's place is refused.

A cluster task writes inside :func:`lenslab.staging.staged`: its temporaries are named for the command's
process and left for the command to rename, so no output appears once the command has ended.
"""

from __future__ import annotations

import contextlib
import os
import stat
import threading
from pathlib import Path
from typing import Iterator


TEMPORARY_TAG = ".tmp-"  # temporaries are named .STEM.tmp-PID-HOST-RANDOM.SUFFIX beside their target
#: set by :func:`lenslab.staging.staged` for the calling thread: ``.owner`` (``PID-HOST``) and ``.written``
STAGING = threading.local()


def _host_tag() -> str:
    """Six hex digits naming this machine: a temporary's process number means something only on its host
    (workers on other machines share the folders). The host name is ``socket.gethostname()``'s (``uname``'s node
    name); SHA-1 is the built-in one when there is one (OpenSSL's, through hashlib, takes a command 2 ms to load)."""
    try:
        from _sha1 import sha1
    except ImportError:  # pragma: no cover  (a Python built without it)
        from hashlib import sha1

    return sha1(os.uname().nodename.encode()).hexdigest()[:6]


HOST = _host_tag()

#: the longest file name, in bytes, of the file systems lenslab writes to (Linux's, macOS's and Windows' NAME_MAX)
NAME_MAX = 255
#: what a temporary's name adds to its target's stem and suffix at most: ``.`` + TEMPORARY_TAG + a process number
#: (10 digits) + ``-HOST-RANDOM`` (6 and 8 hex digits)
TEMPORARY_EXTRA = 1 + len(TEMPORARY_TAG) + 10 + 1 + 6 + 1 + 8
#: a suffix longer than this (in bytes) is no format's extension: a temporary keeps it only within its stem
LONGEST_SUFFIX = 16


def name_bytes(name: str) -> int:
    """The length of file name ``name`` in bytes, as the file system counts it (UTF-8 on Linux)."""
    return len(os.fsencode(name))


def name_too_long(path: str | os.PathLike) -> str | None:
    """What is wrong with ``path`` when its file name is longer than :data:`NAME_MAX` bytes (one line, led by the
    path with the name's first 24 characters, ``...`` and its last 16: a clip's frame ``NAME.000042.exr`` shows
    its number), else None."""
    path = os.fspath(path)
    folder, name = os.path.split(path)
    n = name_bytes(name)
    if n <= NAME_MAX:
        return None
    short = os.path.join(folder, f"{name[:24]}...{name[-16:]}")
    return f"{short}: its name is too long: {n} bytes, where a file name holds at most {NAME_MAX}; give a shorter name"


def temporary_parts(target: Path) -> tuple[str, str]:
    """The stem and suffix a temporary of ``target`` (and the writability probe of its folder) is named with:
    ``target``'s own where the name fits :data:`NAME_MAX` with :data:`TEMPORARY_EXTRA` more bytes; else the
    stem cut (on a character's boundary) to what fits, followed by ``~`` and eight hex digits of the SHA-1 of
    ``target``'s whole name, so the temporaries of two long names that begin alike stay apart and
    :func:`temporaries` finds each one's. The suffix is kept (encoders pick the format by it)."""
    stem, suffix = target.stem, target.suffix
    if name_bytes(suffix) > LONGEST_SUFFIX:
        stem, suffix = target.name, ""
    room = NAME_MAX - TEMPORARY_EXTRA - name_bytes(suffix)
    if name_bytes(stem) <= room:
        return stem, suffix
    try:
        from _sha1 import sha1
    except ImportError:  # pragma: no cover  (a Python built without it)
        from hashlib import sha1

    tag = "~" + sha1(os.fsencode(target.name)).hexdigest()[:8]
    room -= len(tag)
    cut = len(stem)
    while name_bytes(stem[:cut]) > room:
        cut -= 1
    return stem[:cut] + tag, suffix


def temporary_name(target: Path, owner_: str) -> str:
    """The name of a temporary (or a probe) of ``target`` for process ``owner_`` (``PID-HOST``): at most
    :data:`NAME_MAX` bytes whatever ``target``'s name (:func:`temporary_parts`)."""
    stem, suffix = temporary_parts(target)
    return f".{stem}{TEMPORARY_TAG}{owner_}-{os.urandom(4).hex()}{suffix}"


def owner() -> str:
    """This process as a temporary's owner: ``PID-HOST``."""
    return f"{os.getpid()}-{HOST}"


#: set when the command is stopping (Ctrl-C, SIGTERM): a write that finishes then is not renamed
STOPPING = threading.Event()


class Stopped(KeyboardInterrupt):
    """A write finished after the command was told to stop: its temporary was removed, nothing renamed."""


def refuse_special(path: str | os.PathLike) -> None:
    """Raise :class:`OSError` if ``path`` exists and is neither a regular file nor a folder (a FIFO, a
    device, a socket): outputs replace files, never such nodes."""
    try:
        mode = os.stat(path).st_mode
    except OSError:
        return
    if not stat.S_ISREG(mode) and not stat.S_ISDIR(mode):
        from lenslab.errors import OutputError

        raise OutputError(f"{path}: exists and is not a regular file (a FIFO, device or socket); it is never "
                          "replaced, even with --overwrite: choose another output name")


def rename_temporary(tmp: Path, target: Path, overwrite: bool) -> None:
    """Rename a finished temporary to its target: only over a regular file, and only with ``overwrite``."""
    refuse_special(target)
    if overwrite:
        os.replace(tmp, target)
        return
    try:
        os.link(tmp, target)  # fails if the target appeared meanwhile: never clobber
    except FileExistsError:
        raise FileExistsError(f"{target}: already exists; pass overwrite=True (--overwrite) to replace it") from None
    except OSError:  # file systems without hard links
        if target.exists():
            raise FileExistsError(
                f"{target}: already exists; pass overwrite=True (--overwrite) to replace it") from None
        os.replace(tmp, target)


def temporaries(path: str | os.PathLike) -> list[Path]:
    """Temporary files of ``path`` left by writers that were killed before they could rename or remove
    them (a lost cluster worker, a power cut); a batch removes them once no writer of ``path`` runs."""
    import glob

    target = Path(path)
    if not target.parent.is_dir():
        return []
    stem, suffix = temporary_parts(target)
    pattern = f".{glob.escape(stem)}{TEMPORARY_TAG}*{glob.escape(suffix)}"
    return sorted(target.parent.glob(pattern))


@contextlib.contextmanager
def atomic_write_path(path: str | os.PathLike, overwrite: bool = True) -> Iterator[Path]:
    """Yield a temporary path next to ``path``; on success rename it to ``path``, on failure remove it.

    The temporary name keeps the target's extension (some encoders choose the format by it).
    With ``overwrite=False`` an existing target raises :class:`FileExistsError` before anything is
    written, and again at the rename if another process created it in the meantime.
    """
    target = Path(path)
    if target.is_dir():
        raise IsADirectoryError(f"{target}: is a directory; give a file name to write to")
    refuse_special(target)
    if not overwrite and target.exists():
        raise FileExistsError(f"{target}: already exists; pass overwrite=True (--overwrite) to replace it")
    parent = target.parent
    if not parent.is_dir():
        raise FileNotFoundError(f"{target}: the directory {parent} does not exist")
    staging = getattr(STAGING, "owner", None)
    tmp = parent / temporary_name(target, staging or owner())
    try:
        yield tmp
        if not tmp.exists():
            raise FileNotFoundError(f"{target}: nothing was written")
        if STOPPING.is_set():
            raise Stopped(f"{target}: not written: the command was stopped")
        if staging is not None:  # the owner renames it (commit) or removes it (discard)
            STAGING.written.append((tmp, target, overwrite))
            return
        try:
            rename_temporary(tmp, target, overwrite)
        finally:
            if tmp.exists():
                tmp.unlink()
    except BaseException:
        with contextlib.suppress(OSError):
            tmp.unlink()
        raise
