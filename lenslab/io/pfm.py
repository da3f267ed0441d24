"""PFM (portable float map): ``PF`` (RGB) and ``Pf`` (grey), 32-bit floats, rows stored bottom to top.

The third header line is the scale: its sign gives the byte order (negative = little-endian), its
absolute value is kept in ``meta["attributes"]["scale"]`` and NOT applied to the pixels. Readers
disagree on whether to multiply or divide by it, so lenslab leaves the values as stored.
The non-standard ``PF4`` (RGBA) variant is refused rather than misread.

Reading and writing copy rows straight between the file and the array in bottom-to-top order, so the
flip costs nothing beyond the copy the operating system does anyway.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np

from lenslab.errors import FormatError, clip
from lenslab.inputs.limits import check_size

_MAX_HEADER = 256


def _parse_header(path: Path, head: bytes) -> tuple[int, int, int, float, int]:
    """(channels, width, height, scale, payload offset) from the first bytes of a PFM file."""
    if head.startswith(b"PF4"):
        raise FormatError(f"{path}: 'PF4' (RGBA PFM) is a non-standard variant lenslab does not read; "
                          "convert it to EXR, which holds alpha")
    if head[:2] == b"PF":
        channels = 3
    elif head[:2] == b"Pf":
        channels = 1
    else:
        raise FormatError(f"{path}: not a PFM file (magic {head[:2]!r}; expected 'PF' or 'Pf')")
    tokens, pos, n = [], 2, len(head)
    while len(tokens) < 3:
        while pos < n and head[pos:pos + 1].isspace():
            pos += 1
        start = pos
        while pos < n and not head[pos:pos + 1].isspace():
            pos += 1
        if pos >= n:
            raise FormatError(f"{path}: the PFM header is incomplete or damaged (it must be 'PF', the "
                              "width and height, and the scale, each followed by white space)")
        tokens.append(head[start:pos])
    pos += 1  # the single white-space character that ends the header
    try:
        if any(len(t) > 9 for t in tokens[:2]):
            raise ValueError
        width, height = int(tokens[0]), int(tokens[1])
        scale = float(tokens[2])
    except ValueError:
        raise FormatError(f"{path}: the PFM header has a malformed width, height or scale "
                          f"({clip(b' '.join(tokens))})") from None
    if not math.isfinite(scale) or scale == 0.0:
        raise FormatError(f"{path}: the PFM scale must be a non-zero number, got {clip(tokens[2])}")
    check_size(path, width, height)
    return channels, width, height, scale, pos


def read_pfm(path: Path, raw: bool = False) -> tuple[np.ndarray, dict]:
    with open(path, "rb") as f:
        head = f.read(_MAX_HEADER)
        channels, width, height, scale, offset = _parse_header(path, head)
        row_bytes = width * channels * 4
        size = os.fstat(f.fileno()).st_size
        if size - offset < row_bytes * height:
            raise FormatError(f"{path}: the header announces {width} x {height} x {channels} floats "
                              f"({row_bytes * height} bytes) but the file holds {max(size - offset, 0)}; "
                              "it is truncated")
        image = np.empty((height, width, channels), dtype=np.float32)
        rows = [memoryview(image[y]).cast("B") for y in range(height - 1, -1, -1)]  # bottom to top
        if hasattr(os, "preadv"):
            got = _preadv_all(f.fileno(), rows, offset)
        else:  # pragma: no cover - platforms without preadv
            f.seek(offset)
            got = sum(f.readinto(r) for r in rows)
        if got != row_bytes * height:
            raise FormatError(f"{path}: the file ended while reading the pixels; it is truncated")
    little = scale < 0
    if little != (np.little_endian):
        image.byteswap(inplace=True)
    meta = {
        "format": "pfm",
        "bit_depth": 32,
        "sample_type": "float",
        "channels": ["R", "G", "B"] if channels == 3 else ["Y"],
        "display_encoded": False,
        "attributes": {"scale": abs(scale), "byte_order": "little" if little else "big"},
    }
    return image, meta


def write_pfm(tmp: Path, image: np.ndarray, byte_order: str = "little", scale: float = 1.0) -> None:
    """Write a float image (C = 1 or 3) to ``tmp``; little-endian by default."""
    if byte_order not in ("little", "big"):
        raise FormatError(f"PFM byte_order must be 'little' or 'big', not {byte_order!r}")
    if not (math.isfinite(scale) and scale > 0):
        raise FormatError(f"PFM scale must be a positive number, not {scale!r}")
    h, w, c = image.shape
    dtype = np.dtype("<f4" if byte_order == "little" else ">f4")
    data = np.ascontiguousarray(image, dtype=dtype)
    sign = -1.0 if byte_order == "little" else 1.0
    header = _header_bytes(c, w, h, sign * scale)
    rows = [memoryview(data[y]).cast("B") for y in range(h - 1, -1, -1)]  # bottom row first, no copy
    with open(tmp, "wb", buffering=0) as f:
        fd = f.fileno()
        if hasattr(os, "posix_fallocate"):
            try:  # reserving the blocks up front halves the cost of the writes on ext4 and xfs
                os.posix_fallocate(fd, 0, len(header) + data.nbytes)
            except OSError:
                pass
        f.write(header)
        if hasattr(os, "writev"):
            _writev_all(fd, rows)
        else:  # pragma: no cover - platforms without writev
            for row in rows:
                f.write(row)


def _header_bytes(c: int, w: int, h: int, scale: float) -> bytes:
    """The header, with the scale written with trailing zeros (``-1.000...0``, the same number to any
    reader) so that the pixels start at a multiple of 64 bytes: the kernel copies from the (aligned)
    array into the page cache about twice as fast when the file offset is aligned too."""
    head = b"%s\n%d %d\n" % (b"PF" if c == 3 else b"Pf", w, h)
    text = repr(float(scale))
    if "e" not in text and "." in text and "n" not in text:
        text += "0" * (-(len(head) + len(text) + 1) % 64)
    return head + text.encode() + b"\n"


def _preadv_all(fd: int, buffers: list, offset: int, batch: int = 1024) -> int:
    """Fill every buffer in order from ``offset`` with scattered reads; returns the bytes read."""
    total = 0
    for i in range(0, len(buffers), batch):
        pending = buffers[i:i + batch]
        while pending:
            n = os.preadv(fd, pending, offset)
            if n <= 0:
                return total
            offset += n
            total += n
            while pending and n >= len(pending[0]):
                n -= len(pending[0])
                pending.pop(0)
            if pending and n:
                pending[0] = pending[0][n:]
    return total


def _writev_all(fd: int, buffers: list, batch: int = 1024) -> None:
    """Write every buffer in order with gathered writes (few system calls, no copy; 1024 = IOV_MAX)."""
    for i in range(0, len(buffers), batch):
        pending = buffers[i:i + batch]
        while pending:
            n = os.writev(fd, pending)
            while pending and n >= len(pending[0]):
                n -= len(pending[0])
                pending.pop(0)
            if pending and n:
                pending[0] = pending[0][n:]


def declare_pfm(path, **_):
    """:class:`lenslab.io.budget.Declared` of a PFM: every float of the declared image must be present."""
    from lenslab.io.budget import Declared

    with open(path, "rb") as f:
        head = f.read(_MAX_HEADER)
        channels, width, height, _, offset = _parse_header(path, head)
        size = os.fstat(f.fileno()).st_size
    return Declared(width, height, channels, min_bytes=width * height * channels * 4, held=size - offset,
                    what="32-bit samples")
