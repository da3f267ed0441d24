"""Format detection: by magic bytes on reading (a file's name is never trusted), by extension on writing."""

from __future__ import annotations

import os
from pathlib import Path

from lenslab.errors import FormatError

#: format name -> extensions it is written with (the first is the canonical one)
EXTENSIONS = {
    "exr": (".exr",),
    "pfm": (".pfm",),
    "ppm": (".ppm", ".pnm"),
    "pgm": (".pgm",),
    "pbm": (".pbm",),
    "jpg": (".jpg", ".jpeg", ".jpe", ".jfif"),
    "png": (".png",),
}
#: formats holding linear floats (high dynamic range); the others hold display-encoded codes
HDR_FORMATS = frozenset({"exr", "pfm"})
WRITABLE = ("exr", "pfm", "ppm", "pgm", "jpg", "png")
_ALIASES = {"jpeg": "jpg", "pnm": "ppm"}

EXR_MAGIC = b"\x76\x2f\x31\x01"
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
JPG_MAGIC = b"\xff\xd8\xff"


def sniff_bytes(head: bytes) -> str | None:
    """Format name from the first bytes of a file, or None if unknown.

    Returns ``"exr"``, ``"png"``, ``"jpg"``, ``"pfm"`` or ``"pnm"`` (P1..P6; the header says which).
    """
    if head.startswith(EXR_MAGIC):
        return "exr"
    if head.startswith(PNG_MAGIC):
        return "png"
    if head.startswith(JPG_MAGIC):
        return "jpg"
    if len(head) >= 2 and head[0:1] == b"P":
        if head[1:2] in (b"F", b"f"):
            return "pfm"
        if head[1:2] in b"123456" and (len(head) == 2 or head[2:3] in b" \t\r\n\x0b\x0c#"):
            return "pnm"
    return None


def sniff(path: str | os.PathLike) -> str:
    """Format of the file at ``path`` by its magic bytes; OSError if unreadable, FormatError if unknown."""
    p = Path(path)
    if p.is_dir():
        raise IsADirectoryError(f"{p}: is a directory, not an image file")
    with open(p, "rb") as f:
        head = f.read(16)
    fmt = sniff_bytes(head)
    if fmt is None:
        if not head:
            raise FormatError(f"{p}: the file is empty")
        raise FormatError(
            f"{p}: not a recognised image (first bytes {head[:8]!r}); lenslab reads EXR, PFM, PPM/PGM/PBM, "
            "JPG and PNG")
    return fmt


def format_for_path(path: str | os.PathLike, format: str | None = None) -> str:
    """Output format from an explicit ``format`` name or else the file's extension."""
    if format is not None:
        name = _ALIASES.get(format.lower().lstrip("."), format.lower().lstrip("."))
        if name not in WRITABLE:
            raise FormatError(f"unknown output format {format!r}; choose one of {', '.join(WRITABLE)}")
        return name
    ext = Path(path).suffix.lower()
    for name, exts in EXTENSIONS.items():
        if ext in exts and name in WRITABLE:
            return name
    raise FormatError(
        f"{path}: cannot tell the format from the extension {ext!r}; use one of "
        f"{', '.join(e[0] for n, e in EXTENSIONS.items() if n in WRITABLE)} or pass format=")
