"""The one output policy of every command (``lenslab``, ``tracer``, ``python -m gallery``).

- an existing file is replaced only with ``--overwrite``, and only when it is a regular file (never a
  folder, a FIFO or a device node, with or without ``--overwrite``);
- an input is never written over, with or without ``--overwrite`` (the same path, or the same file
  reached through a link: compared by device and inode): a usage error (exit status 2), found from the names
  before any input is read (:func:`refuse_inputs`, which :func:`check_output` and a batch's plan call);
- every file is written to a temporary name and renamed (:func:`lenslab.atomic.atomic_write_path`);
- a batch checks what does not depend on one file before it touches anything, and creates no output
  folder when it cannot start (:func:`check_output_dir` only says what it would create).

Standard library only: every command's parser module imports this, and ``--help`` stays instant.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Iterable

from lenslab.atomic import refuse_special
from lenslab.errors import OutputError, UsageError


def refuse_inputs(outputs: Iterable[str | os.PathLike], inputs: Iterable[str | os.PathLike]) -> None:
    """A :class:`~lenslab.errors.UsageError` (exit status 2) when one of ``outputs`` is one of ``inputs``: the
    same path, or the same file through a link (device and inode). Only names are compared and existing files
    stat'ed (each once, whatever the batch's size): no input is read, so a command calls this first."""
    names, ids = set(), set()
    for src in inputs:
        src = str(src)
        if ":" in src and not os.path.exists(src):  # an EXR part or layer selector: file.exr:left
            src = src.rpartition(":")[0]
        names.add(Path(src).absolute())
        try:
            st = os.stat(src)
            ids.add((st.st_dev, st.st_ino))
        except OSError:
            pass
    for out in map(Path, outputs):
        try:
            st = os.stat(out)
            linked = (st.st_dev, st.st_ino) in ids
        except OSError:
            linked = False
        if linked or out.absolute() in names:
            raise UsageError(f"{out}: is an input of this command; it is never written over, even with "
                             "--overwrite: choose another output name")


def check_output(path: str | os.PathLike, inputs: Iterable[str | os.PathLike] = (), overwrite: bool = False) -> Path:
    """Refuse to write ``path`` when it is one of ``inputs`` (always: :func:`refuse_inputs`, a usage error) or
    exists (unless ``overwrite``: an :class:`OutputError`). Returns ``path`` as a :class:`~pathlib.Path`.
    Nothing is written. Each refusal is the output's own: its line names the output alone (``out.png: already
    exists; ...``), in one file and in a batch, never the input it was made from beside it."""
    try:
        return _check_output(path, inputs, overwrite)
    except Exception as exc:
        exc.lenslab_file = getattr(exc, "lenslab_file", None) or str(path)  # (the funnel and a batch's report name this file, and only it)
        raise


def _check_output(path, inputs, overwrite: bool) -> Path:
    refuse_inputs([path], inputs)
    out = Path(path)
    check_name_length(out)
    if out.is_dir():
        raise UsageError(f"{out}: is a folder; give a file name to write to")
    if os.path.lexists(out) and not overwrite:
        raise OutputError(f"{out}: already exists; give --overwrite to replace it")
    refuse_special(out)
    if not out.parent.is_dir() and str(out.parent) not in ("", "."):
        made = next((p for p in out.parents if os.path.lexists(p)), None)  # the nearest folder there is, or a file
        if made is not None and not made.is_dir():
            raise OutputError(f"{out}: {made} is a file, not a folder")
        raise OutputError(f"{out}: the folder {out.parent} does not exist")
    check_writable(out)
    return out


def check_name_length(out: Path) -> None:
    """An :class:`OutputError` when ``out``'s file name is longer than a file system holds (:data:`~lenslab.atomic.
    NAME_MAX` bytes, UTF-8), said as such before anything is tried; a name that fits gets temporaries that fit too."""
    from lenslab.atomic import name_too_long

    why = name_too_long(out)
    if why:
        exc = OutputError(why)
        exc.lenslab_file = why.partition(": ")[0]  # (the line names the file shortened, once)
        raise exc


def check_writable(out: Path) -> None:
    """An :class:`OutputError` naming ``out`` when its folder does not let a file be made in it (read-only, no
    permission, a virtual file system such as /proc): a file of the temporaries' pattern is created there and
    removed at once, so the refusal comes before any input is read, never at the rename of a finished image."""
    from lenslab.atomic import owner, temporary_name
    from lenslab.errors import stop_signals_held

    folder = out.parent
    probe = folder / temporary_name(out, owner())
    with stop_signals_held():  # a Ctrl-C or SIGTERM landing between the two steps is raised after the removal
        try:
            os.close(os.open(probe, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600))
        except OSError as exc:
            raise OutputError(f"{out}: cannot be written: no file can be made in the folder "
                              f"{folder if str(folder) else '.'} ({exc.strerror or exc})") from None
        try:
            os.unlink(probe)
        except OSError:
            pass


def check_output_dir(path: str | os.PathLike, inputs: int | None = None) -> Path:
    """Check that ``path`` can be an output folder (an existing folder, or a new one whose parent can be
    made); create nothing. Call :func:`make_output_dir` once everything else has been checked. With
    ``inputs`` (how many files go there), a new name with an image extension is taken for a file name
    given by mistake: a usage error."""
    out = Path(path)
    if inputs is not None and not out.is_dir():
        from lenslab.io.registry import input_extensions

        if out.suffix.lower() in input_extensions():
            raise UsageError(f"-o {out} names a file but there are {inputs} inputs; give a folder")
    if out.exists() and not out.is_dir():
        refuse_special(out)  # a device or FIFO (/dev/null): that it is not a regular file is the cause
        raise UsageError(f"{out}: exists and is not a folder; give a folder for several outputs")
    parent = out.absolute().parent
    while not parent.exists():
        parent = parent.parent
    if not parent.is_dir() or not os.access(parent, os.W_OK):
        raise OutputError(f"{out}: cannot be created in {parent}")
    return out


def output_format(path: str | os.PathLike) -> str:
    """The output format an output name asks for; an unknown extension is a usage error (checked before
    any input is read)."""
    from lenslab.errors import FormatError
    from lenslab.io.detect import format_for_path

    try:
        return format_for_path(path)
    except FormatError as exc:
        raise UsageError(str(exc)) from None


def make_output_dir(path: str | os.PathLike, made: list | None = None) -> Path:
    """Create the output folder ``path`` (and its missing parents) once :func:`check_output_dir` says it can
    be; ``made``: a list the folders created are added to, deepest first (for :func:`remove_made_dirs`)."""
    out = check_output_dir(path)
    new = [p for p in (out, *out.parents) if not p.exists()]
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:  # (a read-only or virtual file system): one line that says what could not be done
        raise OutputError(f"{out}: the folder cannot be made ({exc.strerror or exc})") from None
    if made is not None:
        made.extend(new)
    return out


def remove_made_dirs(made: list) -> None:
    """Remove the folders :func:`make_output_dir` created (``made``, deepest first) while they are empty: a
    command that failed having written nothing there leaves nothing behind."""
    for folder in made:
        try:
            folder.rmdir()
        except OSError:  # something was written there (or by another process): kept, and its parents
            return
