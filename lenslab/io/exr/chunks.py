"""Find a truncated or damaged OpenEXR file before the library reads its pixels.

The OpenEXR library reports a chunk that runs past the end of the file on stderr, several lines from its
C core, before the Python bindings raise an exception whose text says nothing of it. Reading the file's
layout first gives one line instead: the header's attributes (name, type, size, value) up to the empty
name, then the offset table (one uint64 per chunk), then each chunk's leader (its first scanline and
packed size, two int32), all little-endian (OpenEXR, "The OpenEXR File Layout"). Only single-part
scanline files are checked this way; tiled and multi-part files are left to the library, and deep files'
chunks are read by :mod:`lenslab.io.exr.deep_counts`, which counts their samples for the budget.

A read parses the header once (:func:`parse_header`): the byte budget (:func:`declare_exr`) gives its
:class:`Layout` to the reader, which checks the chunks and reads the channels' stored types from it; a
command's channel check before its job (:func:`first_part_channels`) takes the same parse, kept for that file.
"""

from __future__ import annotations

import hashlib
import os
import struct
import threading
from collections import OrderedDict
from dataclasses import dataclass

from lenslab.errors import FormatError
from lenslab.inputs.limits import env_int

MAGIC = 20000630
TILED, NON_IMAGE, MULTIPART = 0x200, 0x800, 0x1000
#: scanlines per chunk by the compression attribute's value (NONE, RLE, ZIPS, ZIP, PIZ, PXR24, B44, B44A,
#: DWAA, DWAB)
LINES_PER_CHUNK = (1, 1, 1, 16, 32, 16, 32, 32, 32, 256)
#: the most bytes of a header attribute read as a list of values (``floatvector``, ``stringvector``): OpenEXR's
#: Python bindings build a Python object per value, 8 times the bytes and more (a 32 MB ``floatvector`` took
#: 426 MB); 1 MiB is 262144 floats, more than any camera writes in one attribute. A valid file may hold more (a LUT
#: kept as a vector): the environment variable ``LENSLAB_EXR_VECTOR_BYTES`` raises it, as the refusal says
VECTOR_BYTES = env_int("LENSLAB_EXR_VECTOR_BYTES", 1 << 20)
VECTORS = (b"floatvector", b"stringvector")


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


def check_chunks(path, layout: Layout) -> None:
    """Raise :class:`FormatError` (one line) when a single-part scanline EXR's offset table, or a chunk it
    points to, is cut short by the end of the file; ``layout``: the file's header as :func:`parse_header`
    read it (tiled, multi-part and deep files are left to the library)."""
    if layout.version & (TILED | NON_IMAGE | MULTIPART) or len(layout.parts) != 1:
        return
    part = layout.parts[0]
    compression, window = part.get("compression"), part.get("dataWindow")
    if compression is None or window is None or compression >= len(LINES_PER_CHUNK):
        return
    chunks = _chunks(part)
    size, table_end = layout.size, layout.header_end + 8 * chunks
    if chunks <= 0:
        return
    if table_end > size:
        raise FormatError(f"{path}: the table of its {chunks} chunks ends at byte {table_end} but the file has "
                          f"{size} bytes; the file is truncated")
    with open(path, "rb") as f:
        f.seek(layout.header_end)
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


def _headers(f, size) -> tuple[list[dict], int]:
    """The attributes of interest of every part's header (one for a single-part file), and the version
    field."""
    magic_version = f.read(8)
    if len(magic_version) < 8:
        raise EOFError
    magic, version = struct.unpack("<ii", magic_version)
    if magic != MAGIC:
        raise FormatError(f"{f.name}: not an OpenEXR file")
    multi = bool(version & MULTIPART)
    if version & 0xFF != 2 or version & ~0x1EFF or (multi and version & TILED):
        raise FormatError(f"{f.name}: OpenEXR version field {version:#x} is not version 2 with valid flags; the "
                          "file is damaged")
    parts = []
    while True:
        part = {"tiled": bool(version & TILED) and not multi}
        first = True
        while True:
            name = _cstring(f)
            if not name:
                break
            first = False
            kind = _cstring(f)
            (n,) = struct.unpack("<i", f.read(4))
            if n < 0 or f.tell() + n > size:
                raise EOFError
            if kind in VECTORS and n > VECTOR_BYTES:
                raise FormatError(f"{f.name}: its header attribute {name[:64].decode('utf-8', 'replace')!r} holds "
                                  f"{n:,} bytes of {kind.decode()}, more than the {VECTOR_BYTES:,} lenslab reads of "
                                  "one (OpenEXR's bindings take 13 times its bytes); LENSLAB_EXR_VECTOR_BYTES raises it")
            value = f.read(n)
            if kind == b"box2i" and n == 16 and name in (b"dataWindow", b"displayWindow"):
                part[name.decode()] = struct.unpack("<iiii", value)
            elif (name, kind) == (b"channels", b"chlist"):  # (by name and type, as OpenEXR finds them)
                part["channel_types"] = _channel_list(f.name, value)
                part["channel_names"] = list(part["channel_types"])
                part["channels"] = len(part["channel_names"])
            elif (name, kind) == (b"compression", b"compression") and n == 1:
                part["compression"] = value[0]
            elif (name, kind) == (b"tiles", b"tiledesc") and n == 9:
                part["tiles"] = struct.unpack("<IIB", value)
            elif (name, kind) == (b"name", b"string"):
                part["name"] = value[:256].decode("utf-8", "replace")
            elif (name, kind) == (b"chunkCount", b"int") and n == 4:
                part["chunkCount"] = struct.unpack("<i", value)[0]
            elif name == b"type" and kind == b"string":
                part["tiled"] = value.startswith(b"tiled")
                part["deep"] = value.startswith(b"deep")
                part["deep_tiled"] = value.startswith(b"deeptile")
        if first and multi:
            break  # the empty header that ends a multi-part file's headers
        parts.append(part)
        if not multi:
            break
    return parts, version


#: OpenEXR's pixel type codes (``Imf::PixelType``)
PIXEL_TYPES = {0: "UINT", 1: "HALF", 2: "FLOAT"}


def _channel_list(path, value: bytes) -> dict[str, str]:
    """{name: pixel type} of a ``chlist`` value (each a UTF-8 name, a NUL and 16 bytes: int32 pixel type,
    pLinear, three reserved bytes, int32 x and y sampling; a NUL ends the list)."""
    pos, types = 0, {}
    while pos < len(value) and value[pos] != 0:
        end = value.find(b"\0", pos)
        if end < 0 or end + 17 > len(value):
            raise FormatError(f"{path}: the channel list is damaged")
        try:
            name = value[pos:end].decode("utf-8")
        except UnicodeDecodeError:
            raise FormatError(f"{path}: channel {len(types) + 1}'s name is not UTF-8 text; the file is damaged") from None
        (code,) = struct.unpack("<i", value[end + 1:end + 5])
        types[name] = PIXEL_TYPES.get(code, "UNKNOWN")
        pos = end + 17
    return types


@dataclass(frozen=True)
class Layout:
    """An EXR's header as lenslab reads it, once a read (:func:`parse_header`): each part's attributes of
    interest (``dataWindow``, ``displayWindow`` as (x0, y0, x1, y1), ``channel_types`` {name: HALF, FLOAT or
    UINT} and ``channel_names`` in file order, ``compression`` code, ``tiles`` (x size, y size, mode),
    ``tiled``, ``deep``), where the header ends (the offset tables start), the file's size and version."""

    parts: tuple
    header_end: int
    size: int
    version: int

    @property
    def multipart(self) -> bool:
        return bool(self.version & MULTIPART)

    def first_part(self, path) -> dict:
        if not self.parts or "channel_names" not in self.parts[0]:
            raise FormatError(f"{path}: the OpenEXR header names no channels; the file is damaged")
        return self.parts[0]


#: headers parsed lately, by the file they were read from (see :func:`parse_header`): a command's channel
#: check before its job and the job's read of the same input share one parse. Each entry keeps a digest of the
#: header's bytes too: a hit counts only where the file still starts with them (its stat alone cannot tell a
#: file rewritten in place within a clock tick of a coarse file system)
_PARSED: OrderedDict = OrderedDict()
_PARSED_MAX = 32
#: headers longer than this are parsed each time (a real header is a few kilobytes)
_PARSED_BYTES = 1 << 20
_PARSED_LOCK = threading.Lock()


def _digest(head: bytes) -> bytes:
    return hashlib.blake2b(head, digest_size=16).digest()


def parse_header(path) -> Layout:
    """Read ``path``'s header (every part's) and where it ends: the one parse of lenslab's own that a read
    of an EXR makes (the byte budget, the truncation check and the band reader all take its answer).
    A header cut short or damaged is a :class:`FormatError` of one line.

    The answer is kept for the file it was read from (its device, inode, size and modification and change
    times, taken from the open file, and the header's bytes): asked again about that same file, as a
    command's channel check and then its read are, this returns the same :class:`Layout` (shared: never
    change it) after reading the header's bytes alone (no parse); a file written since is parsed anew,
    whatever its times say (the parse depends on those bytes and the file's size alone)."""
    with open(path, "rb") as f:
        st = os.fstat(f.fileno())
        key = (os.path.abspath(path), st.st_dev, st.st_ino, st.st_size, st.st_mtime_ns, st.st_ctime_ns)
        with _PARSED_LOCK:
            kept = _PARSED.get(key)
        if kept is not None:
            layout, digest = kept
            if _digest(f.read(layout.header_end)) == digest:
                with _PARSED_LOCK:
                    if key in _PARSED:
                        _PARSED.move_to_end(key)
                return layout
            f.seek(0)
        try:
            parts, version = _headers(f, st.st_size)
            layout = Layout(tuple(parts), f.tell(), st.st_size, version)
        except (EOFError, struct.error):
            raise FormatError(f"{path}: the OpenEXR header ends early or is damaged ({st.st_size} bytes); the "
                              "file is truncated or damaged") from None
        if layout.header_end > _PARSED_BYTES:
            return layout
        f.seek(0)
        digest = _digest(f.read(layout.header_end))
    with _PARSED_LOCK:
        _PARSED[key] = (layout, digest)
        while len(_PARSED) > _PARSED_MAX:
            _PARSED.popitem(last=False)
    return layout


def first_part_channels(path) -> list[str]:
    """The channel names of an EXR's first part, from lenslab's own reading of the header (no pixel is
    decoded, and OpenEXR never sees the file)."""
    return parse_header(path).first_part(path)["channel_names"]


def _chunks(part) -> int:
    x0, y0, x1, y1 = part["dataWindow"]
    w, h = x1 - x0 + 1, y1 - y0 + 1
    if part.get("tiled") and "tiles" in part:
        tx, ty, _ = part["tiles"]
        return -(-w // max(tx, 1)) * -(-h // max(ty, 1))
    comp = part.get("compression", 0)
    return -(-h // (LINES_PER_CHUNK[comp] if comp < len(LINES_PER_CHUNK) else 1))


def declare_exr(path, data_window: bool = False, **_):
    """:class:`lenslab.io.budget.Declared` of an EXR: the largest part's display window (its data window
    with ``data_window=True``), and the offset tables and chunk leaders every chunk of it needs; its
    ``parsed`` is the :class:`Layout` read, which the reader takes back (the header is parsed once)."""
    from lenslab.io.budget import Declared

    layout = parse_header(path)
    parts, size, header_end = layout.parts, layout.size, layout.header_end
    if not parts:
        raise FormatError(f"{path}: the OpenEXR header declares no part; the file is damaged")
    best, table, hint = None, 0, ""
    for part in parts:
        if "dataWindow" not in part or "displayWindow" not in part:
            raise FormatError(f"{path}: the OpenEXR header of a part lacks its data or display window; the file is "
                              "damaged")
        for name in ("dataWindow", "displayWindow"):
            x0, y0, x1, y1 = part[name]
            if x1 < x0 or y1 < y0:
                raise FormatError(f"{path}: the {name} ({x0}, {y0}) - ({x1}, {y1}) is empty or inverted; the file "
                                  "is damaged")
        x0, y0, x1, y1 = part["dataWindow" if data_window else "displayWindow"]
        d = Declared(x1 - x0 + 1, y1 - y0 + 1, min(part.get("channels", 4) or 1, 4))
        if best is None or d.float_bytes > best.float_bytes:
            best = d
            x0, y0, x1, y1 = part["dataWindow"]
            if not data_window and (x1 - x0 + 1) * (y1 - y0 + 1) < d.width * d.height:
                hint = (f"; its data window alone is {x1 - x0 + 1} x {y1 - y0 + 1} (read it with --data-window, "
                        "or data_window=True)")
        if not part.get("deep"):
            leader = (20 if part.get("tiled") else 8) + (4 if len(parts) > 1 else 0)
            table += _chunks(part) * (8 + leader)
    declared = Declared(best.width, best.height, best.channels, min_bytes=table, held=size - header_end,
                        what="chunk tables and chunk leaders", hint=hint, parsed=layout)
    if any(part.get("deep") for part in parts):  # the flat image first, then the samples its tables count
        from lenslab.io.budget import check
        from lenslab.io.exr.deep_counts import check_deep

        check(path, declared, size)
        check_deep(path, layout)
    return declared
