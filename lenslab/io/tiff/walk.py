"""The low-level reading of a TIFF structure, shared by the TIFF reader's pre-check (:mod:`lenslab.io.tiff.layout`),
the Exif block parser (:mod:`lenslab.io.exif.ifd`) and its TIFF writer: the header and byte order, an IFD's entries, an
entry's values (in its value field or at its offset), each checked against the ``size`` bytes held before it is read
(through ``read(offset, n)``: no pixel is loaded), and a chain of IFDs with loops and runaway chains refused. What
each caller refuses or notes, and how it says so, stays with it. Classic TIFF (``II*\\0``/``MM\\0*``: 2-byte
entry counts, 12-byte entries, 4-byte offsets) and BigTIFF (``+``: 8-byte counts, 20-byte entries, 8-byte offsets), as
the TIFF 6.0 specification and the BigTIFF design note lay them out.

>>> block = b"II*\\0" + bytes([8, 0, 0, 0, 1, 0, 0x0F, 1, 2, 0, 4, 0, 0, 0]) + b"Big\\0" + bytes(4)
>>> found = header(block[:16])
>>> found.order, found.big, found.first, list(entries(lambda at, n: block[at:at + n], len(block), found.first, "<")[0])
('<', False, 8, [(271, 2, 4, b'Big\\x00')])
"""

from __future__ import annotations

import struct
from collections import namedtuple

#: the struct code of one value of each TIFF type (1 BYTE, 2 ASCII, 3 SHORT, 4 LONG, 5 RATIONAL, 6 SBYTE,
#: 7 UNDEFINED, 8 SSHORT, 9 SLONG, 10 SRATIONAL, 11 FLOAT, 12 DOUBLE, 13 IFD; BigTIFF's 16 LONG8, 17 SLONG8, 18 IFD8)
CODES = {1: "B", 2: "B", 3: "H", 4: "I", 5: "II", 6: "b", 7: "B", 8: "h", 9: "i", 10: "ii", 11: "f", 12: "d",
         13: "I", 16: "Q", 17: "q", 18: "Q"}
#: bytes of one value of each type
SIZES = {kind: struct.calcsize("<" + code) for kind, code in CODES.items()}


class Outside(ValueError):
    """``(part, at, count)``: the ``part`` (``count``: an IFD's entry count; ``entries``: its entries; ``value``: an
    entry's values) at byte ``at`` lies outside the bytes held (``count``: the entries an IFD declares)."""


class Loop(ValueError):
    """``(page, back_to)``: IFD ``page`` of a chain (from 1) points back to IFD ``back_to``; None: the chain runs
    past the IFDs followed."""


#: a TIFF header: byte order (``<``, ``>``), version (42; 43 BigTIFF), the first IFD's offset (None: a BigTIFF header
#: cut short), whether it is a standard one (42, or 43 with 8-byte offsets), whether it is BigTIFF's
Header = namedtuple("Header", "order version first standard big")


def header(head: bytes) -> Header | None:
    """The header of ``head`` (the first 16 bytes or fewer), None where it has no byte order mark or fewer than 8."""
    order = {b"II": "<", b"MM": ">"}.get(bytes(head[:2]))
    if order is None or len(head) < 8:
        return None
    version = struct.unpack(order + "H", head[2:4])[0]
    if version != 43:
        return Header(order, version, struct.unpack(order + "I", head[4:8])[0], version == 42, False)
    first = struct.unpack(order + "Q", head[8:16])[0] if len(head) >= 16 else None
    return Header(order, 43, first, first is not None and struct.unpack(order + "HH", head[4:8]) == (8, 0), True)


def file_read(f):
    """``read(offset, n)`` of the open binary file ``f``."""
    return lambda at, n: (f.seek(at), f.read(n))[1]


def entries(read, size: int, at: int, order: str, big: bool = False, chained: bool = False, lowest: int = 0,
            held: bool = False):
    """``(entries, next)`` of the IFD at ``at``: an iterator of its entries, each (tag, type, count, value field: 4
    bytes, a BigTIFF's 8), and the offset of the next IFD where ``chained`` (None otherwise, and its field need not be
    held). Raises :class:`Outside` where the IFD begins before ``lowest`` or it runs past ``size`` (``held``: its
    entries that ``size`` holds are given instead)."""
    head, entry, layout, offset = (8, 20, "HHQ8s", "Q") if big else (2, 12, "HHI4s", "I")
    if at < lowest or at + head > size:
        raise Outside("count", at, None)
    count = struct.unpack(order + ("Q" if big else "H"), read(at, head))[0]
    n = entry * count + (struct.calcsize(offset) if chained else 0)
    if at + head + n > size and held:
        count = (size - at - head) // entry
        n = entry * count
    elif at + head + n > size:
        raise Outside("entries", at + head, count)
    raw = read(at + head, n)
    found = struct.iter_unpack(order + layout, memoryview(raw)[:entry * count])  # (unpacked as it is walked)
    return found, struct.unpack(order + offset, raw[entry * count:])[0] if chained else None


def value_bytes(read, size: int, order: str, kind: int, count: int, field: bytes, n: int | None = None) -> bytes:
    """The first ``n`` bytes (all where None) of the ``count`` values of type ``kind`` of an entry whose value field
    is ``field``: in the field where all fit in it, else at the offset it holds (:class:`Outside` where they run past
    ``size``)."""
    total = SIZES[kind] * count
    n = total if n is None else n
    if total <= len(field):
        return field[:n]
    at = struct.unpack(order + ("Q" if len(field) == 8 else "I"), field)[0]
    if at + n > size:
        raise Outside("value", at, None)
    return read(at, n)


def chain(read, size: int, found: Header, limit: int):
    """Every IFD of the chain from ``found``'s first, as :func:`entries`; :class:`Loop` where one points back to one
    before it or the chain runs past ``limit`` IFDs."""
    seen: dict[int, int] = {}
    at = found.first
    while at:
        if at in seen:
            raise Loop(len(seen) + 1, seen[at] + 1)
        if len(seen) >= limit:
            raise Loop(limit + 1, None)
        seen[at] = len(seen)
        found_entries, at = entries(read, size, at, found.order, found.big, chained=True)
        yield found_entries
