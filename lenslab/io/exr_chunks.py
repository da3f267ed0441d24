"""Find a truncated or damaged OpenEXR file before the library reads its pixels.

The OpenEXR library reports a chunk that runs past the end of the file on stderr, several lines from its
C core, before the Python bindings raise an exception whose text says nothing of it. Reading the file's
layout first gives one line instead: the header's attributes (name, type, size, value) up to the empty
name, then the offset table (one uint64 per chunk), then each chunk's leader (its first scanline and
packed size, two int32), all little-endian (OpenEXR, "The OpenEXR File Layout"). Only single-part
scanline files are checked this way; tiled, multi-part and deep files are left to the library.
"""

from __future__ import annotations

import os
import struct

from lenslab.errors import FormatError

MAGIC = 20000630
TILED, NON_IMAGE, MULTIPART = 0x200, 0x800, 0x1000
#: scanlines per chunk by the compression attribute's value (NONE, RLE, ZIPS, ZIP, PIZ, PXR24, B44, B44A,
#: DWAA, DWAB)
LINES_PER_CHUNK = (1, 1, 1, 16, 32, 16, 32, 32, 32, 256)


def _cstring(f, limit: int = 256) -> bytes:
    out = bytearray()
    while len(out) <= limit:
        c = f.read(1)
        if not c:
            raise EOFError
        if c == b"\0":
            return bytes(out)
        out += c
    raise EOFError  # no name or type is this long: not a header


def check_chunks(path) -> None:
    """Raise :class:`FormatError` (one line) when a single-part scanline EXR's header, offset table or a
    chunk it points to is cut short by the end of the file; any other layout passes unchecked."""
    try:
        _check(path)
    except (EOFError, struct.error):  # (FormatError, a ValueError, says more and passes through)
        raise FormatError(f"{path}: the header ends early or is damaged ({os.path.getsize(path)} bytes); the file "
                          "is truncated or damaged") from None


def _check(path) -> None:
    size = os.path.getsize(path)
    with open(path, "rb") as f:
        head = f.read(8)
        if len(head) < 8:
            raise EOFError
        magic, version = struct.unpack("<ii", head)
        if magic != MAGIC or version & (TILED | NON_IMAGE | MULTIPART):
            return
        compression, window = None, None
        while True:
            name = _cstring(f)
            if not name:
                break
            kind = _cstring(f)
            (n,) = struct.unpack("<i", f.read(4))
            if n < 0 or f.tell() + n > size:
                raise EOFError
            value = f.read(n)
            if name == b"compression" and kind == b"compression" and n == 1:
                compression = value[0]
            elif name == b"dataWindow" and kind == b"box2i" and n == 16:
                window = struct.unpack("<iiii", value)
        if compression is None or window is None or compression >= len(LINES_PER_CHUNK):
            return
        lines = LINES_PER_CHUNK[compression]
        chunks = -(-(window[3] - window[1] + 1) // lines)
        table_end = f.tell() + 8 * chunks
        if chunks <= 0:
            return
        if table_end > size:
            raise FormatError(f"{path}: the table of its {chunks} chunks ends at byte {table_end} but the file has "
                              f"{size} bytes; the file is truncated")
        offsets = struct.unpack(f"<{chunks}Q", f.read(8 * chunks))
        for i, off in enumerate(offsets):
            end = off + 8
            if off >= table_end and end <= size:
                f.seek(off)
                _, packed = struct.unpack("<ii", f.read(8))
                end += max(packed, 0)
            if off < table_end or end > size:
                raise FormatError(f"{path}: chunk {i + 1} of {chunks} " + (
                    "was never written" if off == 0 else f"ends at byte {end} but the file has {size} bytes")
                    + "; the file is truncated or damaged")
