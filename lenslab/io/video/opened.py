"""The clip a probe opened, held open for the decoder that follows it.

A clip's warp probes its input (the budget's check, :func:`lenslab.io.video.clips.probe_video`) and then decodes it
(:func:`lenslab.io.video.clips.read_frames`). Opening a clip runs FFmpeg's probe of its streams, which reads and
decodes its first packets. The probe's open container is held here, one at a time, by the file's identity (path,
size, modification time, inode, status-change time); the decoder takes it when it reads that same file and decodes
from its first packet, as from a fresh open (the probe's packets are buffered in it). A container nobody takes is
closed when the next is held."""

from __future__ import annotations

import os
import threading
from contextlib import contextmanager

_held: dict = {}  # identity -> (open container, the thread whose probe opened it) (at most one)
_lock = threading.Lock()


def identity(path):
    """``(absolute path, size, modification time in ns, inode, status-change time in ns)`` of a file; None when it
    cannot be read. The status-change time tells a file rewritten in place whose size and modification time were
    kept (``rsync -t``, ``cp -p``): every write sets it, and it cannot be set back."""
    try:
        st = os.stat(path)
    except (OSError, TypeError, ValueError):
        return None
    return os.path.abspath(path), st.st_size, st.st_mtime_ns, st.st_ino, st.st_ctime_ns


@contextmanager
def probing(container, key):
    """``with probing(av.open(path), identity(path)) as c:`` the container, closed if the block raises, else held
    for :func:`take` (closed when ``key`` is None)."""
    try:
        yield container
    except BaseException:
        container.close()
        raise
    if key is None:
        container.close()
        return
    with _lock:
        old = list(_held.values())
        _held.clear()
        _held[key] = container, threading.get_ident()
    for c, _ in old:
        c.close()


def take(key):
    """The container held for ``key``, now the caller's to close; None when none is held for it."""
    with _lock:
        held = None if key is None else _held.pop(key, None)
    return None if held is None else held[0]


def release(every: bool = False) -> None:
    """Close the container held for a decoder that did not come: the one the calling thread's probe opened (its job
    has ended), or with ``every`` any (the command has ended)."""
    me = threading.get_ident()
    with _lock:
        gone = [_held.pop(k)[0] for k, (_, thread) in list(_held.items()) if every or thread == me]
    for c in gone:
        c.close()


__all__ = ["identity", "probing", "take", "release"]
