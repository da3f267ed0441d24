"""Atomic output: every file is written to a temporary name in the target's directory, then renamed.

A reader never sees a half-written file, and a failure (an exception, a full disk, Ctrl-C) leaves
nothing behind but what was there before.
"""

from __future__ import annotations

import contextlib
import os
import secrets
from pathlib import Path
from typing import Iterator


TEMPORARY_TAG = ".tmp-"  # temporaries are named .STEM.tmp-PID-RANDOM.SUFFIX beside their target


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
    if not overwrite and target.exists():
        raise FileExistsError(f"{target}: already exists; pass overwrite=True (--overwrite) to replace it")
    parent = target.parent
    if not parent.is_dir():
        raise FileNotFoundError(f"{target}: the directory {parent} does not exist")
    tmp = parent / f".{target.stem}{TEMPORARY_TAG}{os.getpid()}-{secrets.token_hex(4)}{target.suffix}"
    try:
        yield tmp
        if not tmp.exists():
            raise FileNotFoundError(f"{target}: nothing was written")
        if overwrite:
            os.replace(tmp, target)
        else:
            try:
                os.link(tmp, target)  # fails if the target appeared meanwhile: never clobber
            except FileExistsError:
                raise FileExistsError(
                    f"{target}: already exists; pass overwrite=True (--overwrite) to replace it") from None
            except OSError:  # file systems without hard links
                if target.exists():
                    raise FileExistsError(
                        f"{target}: already exists; pass overwrite=True (--overwrite) to replace it") from None
                os.replace(tmp, target)
            finally:
                if tmp.exists():
                    tmp.unlink()
    except BaseException:
        with contextlib.suppress(OSError):
            tmp.unlink()
        raise
