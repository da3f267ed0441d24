"""Temporaries beyond one write: a cluster task's outputs left for the command to rename (:func:`staged`,
:func:`commit`, :func:`discard`), and the sweep of temporaries whose process died (:func:`sweep`).

A temporary is named ``.STEM.tmp-PID-HOST-RANDOM.SUFFIX`` (:mod:`lenslab.atomic`): the process and the
machine that own it. A sweep removes only those of this machine whose process no longer runs.
"""

from __future__ import annotations

import contextlib
import os
import re
from pathlib import Path
from typing import Iterator

from lenslab.atomic import HOST, STAGING, TEMPORARY_TAG, rename_temporary

_TEMPORARY = re.compile(r"^\..+" + re.escape(TEMPORARY_TAG) + r"(\d+)-(?:([0-9a-f]{6})-)?[0-9a-f]{8}(\.[^./]*)?$")


def owner_alive(pid: int) -> bool:
    """Whether process ``pid`` runs on this machine (a process of another user counts as running). A zombie, a
    process that has ended but that its parent has not yet waited for (a killed command whose parent is a
    container's first process that reaps no child), runs no more: it writes nothing."""
    if pid <= 0:
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return not _zombie(pid)


def _zombie(pid: int) -> bool:
    """Whether ``pid`` is a zombie, as Linux's ``/proc/PID/stat`` says (its state, the field after the name in
    parentheses, is ``Z``); False where there is no such file (another system, a process gone meanwhile)."""
    try:
        with open(f"/proc/{pid}/stat", "rb") as f:
            stat = f.read(4096)
    except OSError:
        return False
    return stat[stat.rfind(b")") + 1:].split()[:1] == [b"Z"]


def sweep(folders) -> list[Path]:
    """Remove the temporaries in ``folders`` whose owner process no longer runs on this machine (killed
    before it could rename or remove them); returns what was removed. Temporaries of running processes,
    and of processes of other machines, stay."""
    removed = []
    for folder in {Path(f) for f in folders}:
        try:
            names = [e.name for e in os.scandir(folder) if e.name.startswith(".") and TEMPORARY_TAG in e.name]
        except OSError:
            continue
        for name in names:
            m = _TEMPORARY.match(name)
            if m and m.group(2) in (None, HOST) and not owner_alive(int(m.group(1))):
                with contextlib.suppress(OSError):
                    (folder / name).unlink()
                    removed.append(folder / name)
    return removed


@contextlib.contextmanager
def staged(owner: str) -> Iterator[list]:
    """Inside (this thread only), :func:`atomic_write_path` leaves each finished temporary in place, named
    for process ``owner`` (``PID-HOST``, :func:`owner`), and records ``(temporary, target, overwrite)`` in the yielded list; the owner
    renames them with :func:`commit` or removes them with :func:`discard`."""
    saved = getattr(STAGING, "owner", None), getattr(STAGING, "written", None)
    STAGING.owner, STAGING.written = owner, []
    try:
        yield STAGING.written
    except BaseException:
        discard(STAGING.written)
        raise
    finally:
        STAGING.owner, STAGING.written = saved


def commit(written: list) -> None:
    """Rename staged temporaries to their targets (see :func:`staged`); a target that appeared meanwhile
    is kept unless the write was to overwrite it. What cannot be renamed is removed, and the first error
    raised after all were tried."""
    error = None
    for tmp, target, overwrite in written:
        try:
            rename_temporary(Path(tmp), Path(target), overwrite)
        except OSError as exc:
            error = error or exc
        finally:
            with contextlib.suppress(OSError):
                Path(tmp).unlink()
    if error is not None:
        raise error


def discard(written: list) -> None:
    """Remove staged temporaries (the command stopped, or the task failed)."""
    for tmp, _, _ in written:
        with contextlib.suppress(OSError):
            Path(tmp).unlink()
    written.clear()


__all__ = ["staged", "commit", "discard", "sweep", "owner_alive"]
