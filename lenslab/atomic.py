"""Atomic output: every file is written to a temporary name in the target's directory, then renamed.

A reader never sees a half-written file, and a failure (an exception, a full disk, Ctrl-C, SIGTERM)
leaves nothing behind but what was there before. A temporary is named for the process that owns it
(``.STEM.tmp-PID-HOST-RANDOM.SUFFIX``): one left by a process that died (SIGKILL, a lost machine) is
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
    pattern = f".{glob.escape(target.stem)}{TEMPORARY_TAG}*{glob.escape(target.suffix)}"
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
    tmp = parent / f".{target.stem}{TEMPORARY_TAG}{staging or owner()}-{os.urandom(4).hex()}{target.suffix}"
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
