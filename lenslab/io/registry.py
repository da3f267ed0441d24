"""The one registry of file formats, built from the plugins in :mod:`lenslab.io.formats`.

Every module in that package with a ``FORMATS`` tuple of :class:`lenslab.io.plugin.Format` records
is a plugin; nothing else needs to name it. Reading detects the format by magic bytes (a file's name
is never trusted); writing takes it from an explicit name or the output's extension.
"""

from __future__ import annotations

import functools
import importlib
import os
import pkgutil
from pathlib import Path

from lenslab.errors import FormatError
from lenslab.io.plugin import Format
from lenslab.registry import Registry

#: bytes read from the start of a file for detection
HEAD_BYTES = 32


@functools.lru_cache(maxsize=1)
def formats() -> Registry[Format]:
    """Every format by name, in plugin-module order (a :class:`lenslab.registry.Registry`: the extensions
    that name one format only, such as ``jpeg`` or ``tif``, are its aliases; its record's fields are its
    capabilities)."""
    import lenslab.io.formats as package

    found: list[Format] = []
    for info in sorted(pkgutil.iter_modules(package.__path__), key=lambda m: m.name):
        module = importlib.import_module(f"{package.__name__}.{info.name}")
        found.extend(getattr(module, "FORMATS", ()))
    names = [f.name for f in found]
    stems = [e.lstrip(".") for f in found for e in f.extensions]
    table: Registry[Format] = Registry("format", FormatError)
    for fmt in found:
        aliases = tuple(dict.fromkeys(e.lstrip(".") for e in fmt.extensions
                                      if e.lstrip(".") not in names and stems.count(e.lstrip(".")) == 1))
        caps = {k: v for k, v in fmt.describe().items() if k not in ("name", "title", "note")}
        table.add(fmt.name, fmt, aliases=aliases, summary=fmt.title, capabilities=caps)
    return table


def readable() -> tuple[str, ...]:
    return tuple(n for n, f in formats().items() if f.readable)


def writable() -> tuple[str, ...]:
    return tuple(n for n, f in formats().items() if f.writable)


def hdr_formats() -> frozenset[str]:
    """Formats that hold linear floats (no tone curve on writing)."""
    return frozenset(n for n, f in formats().items() if f.hdr)


def input_extensions() -> frozenset[str]:
    """Extensions of every readable format (for picking files out of a directory)."""
    return frozenset(e for f in formats().values() if f.readable for e in f.extensions)


def _titles(names) -> str:
    return ", ".join(formats()[n].title for n in names)


def get(name: str) -> Format:
    """The record of a format by name or extension (``"jpeg"``, ``".tif"``); FormatError listing the names."""
    key = name.lower().lstrip(".")
    table = formats()
    if key in table:
        return table[key]
    for fmt in table.values():
        if "." + key in fmt.extensions:
            return fmt
    raise FormatError(f"unknown format {name!r}; lenslab knows {', '.join(table)}")


def sniff_bytes(head: bytes) -> str | None:
    """Format name from the first bytes of a file, or None if no plugin recognises them."""
    for fmt in formats().values():
        if fmt.readable and fmt.magic(head):
            return fmt.name
    return None


def sniff(path: str | os.PathLike) -> str:
    """The format of a file by its magic bytes, never its name.

    Parameters
    ----------
    path : str or os.PathLike
        The file.

    Returns
    -------
    str
        A format name of ``lenslab info --formats`` (``exr``, ``hdr``, ``tiff``, ``pfm``, ``ppm``...).

    Raises
    ------
    lenslab.errors.FormatError
        Bytes no format recognises, or a path that is not a regular file (a FIFO, device or socket).
    OSError
        A file that cannot be read (``IsADirectoryError`` for a directory).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> import numpy as np, lenslab
    >>> from lenslab.io import sniff
    >>> tmp = pathlib.Path(tempfile.mkdtemp())
    >>> path = lenslab.write(tmp / "image.pfm", np.zeros((2, 2, 3)))
    >>> renamed = path.rename(tmp / "image.jpg")  # a wrong name does not fool it
    >>> sniff(renamed)
    'pfm'
    """
    p = Path(path)
    if p.is_dir():
        raise IsADirectoryError(f"{p}: is a directory, not an image file")
    import stat

    if p.exists() and not stat.S_ISREG(p.stat().st_mode):  # a FIFO would block, a device never end
        raise FormatError(f"{p}: not a regular file (a device, FIFO or socket); give an image file")
    with open(p, "rb") as f:
        head = f.read(HEAD_BYTES)
    name = sniff_bytes(head)
    if name is None:
        if not head:
            raise FormatError(f"{p}: the file is empty")
        raise FormatError(f"{p}: not a recognised image (first bytes {head[:8]!r}); lenslab reads "
                          f"{_titles(readable())}")
    return name


def format_for_path(path: str | os.PathLike, format: str | None = None) -> str:
    """Output format from an explicit ``format`` name or else the file's extension."""
    if format is not None:
        try:
            fmt = get(format)
        except FormatError:
            fmt = None
        if fmt is None or not fmt.writable:
            raise FormatError(f"unknown output format {format!r}; choose one of {', '.join(writable())}")
        return fmt.name
    ext = Path(path).suffix.lower()
    for fmt in formats().values():
        if fmt.writable and ext in fmt.extensions:
            return fmt.name
    exts = ", ".join(formats()[n].extensions[0] for n in writable())
    for fmt in formats().values():  # a format lenslab reads only (HEIC): said as such
        if ext and ext in fmt.extensions and fmt.kind == "video":  # clips are written by convert and warp alone
            raise FormatError(f"{path}: a clip is written by 'lenslab convert' (images or clips to -o {path}) and "
                              f"'lenslab warp', not as one image; name an image file, ending with one of {exts}")
        if ext and ext in fmt.extensions:
            raise FormatError(f"{path}: lenslab reads {fmt.title} but does not write it; end the name with one of "
                              f"{exts}")
    what = f"the extension {ext!r}" if ext else "a name without an extension"
    raise FormatError(f"{path}: cannot tell the output format from {what}; end the name with one of {exts}")
