"""The TIFF structure of an Exif block (TIFF 6.0 section 2; CIPA DC-008): its carried tags read, and a block of them
built.

Reading goes through ``read(offset, n)`` over a block of ``size`` bytes (a JPEG's APP1 payload, a PNG's eXIf chunk,
a TIFF file itself), so a TIFF's tags are read without loading its pixels. Only the first IFD and the Exif IFD it
points to are walked; every offset and count is checked against ``size`` before it is followed, so a damaged or
hostile block raises :class:`Damaged` and never reads past its end nor loops.

>>> block = build({"Make": "Acme", "FocalLengthIn35mmFilm": 26})
>>> tags, odd = parse(lambda at, n: block[at:at + n], len(block))
>>> tags, odd
({'Make': 'Acme', 'Orientation': 1, 'FocalLengthIn35mmFilm': 26}, [])
"""

from __future__ import annotations

import struct
from fractions import Fraction

from lenslab.exif_tags import BY_NUMBER, EXIF_POINTER, EXIF_VERSION, TAGS, TEXT_MAX, checked

#: bytes of one value of each TIFF type (1 BYTE, 2 ASCII, 3 SHORT, 4 LONG, 5 RATIONAL, 7 UNDEFINED, 9 SLONG,
#: 10 SRATIONAL, 13 IFD)
SIZES = {1: 1, 2: 1, 3: 2, 4: 4, 5: 8, 6: 1, 7: 1, 8: 2, 9: 4, 10: 8, 11: 4, 12: 8, 13: 4}
#: the TIFF types each kind of tag is read from
#: (a rational also from FLOAT and DOUBLE, 11 and 12, as Pillow writes a float: written back as a RATIONAL)
READ_TYPES = {"text": (2,), "int": (1, 3, 4, 13), "ratio": (5, 10, 11, 12)}


class Damaged(ValueError):
    """An Exif block whose structure cannot be followed (a header, an IFD or a value beyond its end)."""


def _entries(read, size: int, at: int, order: str, big: bool = False) -> list[tuple[int, int, int, bytes]]:
    """Every entry (tag, type, count, value field: 4 bytes, a BigTIFF's 8) of the IFD at ``at``."""
    head, entry, layout = (8, 20, "HHQ8s") if big else (2, 12, "HHI4s")
    if at < 2 * head or at + head > size:
        raise Damaged(f"an IFD at byte {at} lies outside its {size} bytes")
    count = struct.unpack(order + ("Q" if big else "H"), read(at, head))[0]
    if at + head + entry * count > size:
        raise Damaged(f"the IFD at byte {at} declares {count} entries, more than its {size} bytes hold")
    raw = read(at + head, entry * count)
    return [struct.unpack(order + layout, raw[entry * k:entry * (k + 1)]) for k in range(count)]


def _value(read, size: int, order: str, name: str, kind: int, count: int, field: bytes):
    """The checked value of carried tag ``name``, or None where its type or count is not one the tag takes."""
    tag = TAGS[name]
    if kind not in READ_TYPES[tag.kind] or count < 1 or (tag.kind == "text" and count > TEXT_MAX + 1):
        return None
    n = SIZES[kind] * (count if tag.kind == "text" else 1)  # (a number: its first value, as exiftool shows it)
    if SIZES[kind] * count <= len(field):
        data = field[:n]
    else:
        at = struct.unpack(order + ("Q" if len(field) == 8 else "I"), field)[0]
        if at + n > size:
            raise Damaged(f"{name}'s value at byte {at} lies outside its {size} bytes")
        data = read(at, n)
    if tag.kind == "text":
        return checked(name, data)
    if kind in (5, 10):
        num, den = struct.unpack(order + ("II" if kind == 5 else "ii"), data)
        return checked(name, Fraction(num, den)) if den else None
    if kind in (11, 12):  # (NaN and infinity: no value, as checked says)
        from lenslab.exif_tags import single_ratio

        number = struct.unpack(order + ("f" if kind == 11 else "d"), data)[0]
        return checked(name, single_ratio(number) if kind == 11 else number)
    return checked(name, struct.unpack(order + {1: "B", 3: "H", 4: "I", 13: "I"}[kind], data)[0])


def parse(read, size: int) -> tuple[dict, list[str]]:
    """(the carried tags the block holds, the names of those whose type, count or value is none the tag takes)."""
    head = read(0, 16) if size >= 16 else read(0, 8) if size >= 8 else b""
    order = {b"II": "<", b"MM": ">"}.get(head[:2])
    magic = struct.unpack(order + "H", head[2:4])[0] if order else None
    big = magic == 43 and struct.unpack(order + "HH", head[4:8]) == (8, 0)  # BigTIFF: 8-byte offsets
    if not (magic == 42 or big) or (big and len(head) < 16):
        raise Damaged("no TIFF header (II or MM, 42; or BigTIFF's 43)")
    tags, odd = {}, []
    ifds = [("0", struct.unpack(order + ("Q" if big else "I"), head[8:16] if big else head[4:8])[0])]
    for ifd, at in ifds:
        for number, kind, count, field in _entries(read, size, at, order, big):
            wide = big and kind in (16, 18)  # (LONG8, IFD8: a BigTIFF's)
            if ifd == "0" and number == EXIF_POINTER and (kind in (4, 13) or wide) and count == 1 and len(ifds) == 1:
                pointer = struct.unpack(order + ("Q" if wide else "I"), field[:8 if wide else 4])[0]
                ifds.append(("exif", pointer))  # (followed once: no loop)
            name = BY_NUMBER.get((ifd, number))
            if name is None or name in tags:
                continue
            value = _value(read, size, order, name, kind, count, field)
            if value is None:
                odd.append(name)
            else:
                tags[name] = value
    return tags, odd


def rational(value: Fraction) -> tuple[int, int]:
    """``value`` as an unsigned RATIONAL: exact where both terms fit 32 bits, else the nearest that fits."""
    top = 0xFFFFFFFF
    if value.numerator <= top and value.denominator <= top:
        return value.numerator, value.denominator
    near = value.limit_denominator(top if value <= 1 else max(1, int(top / value)))
    return min(near.numerator, top), near.denominator


def encode(name: str, value) -> tuple[int, int, bytes]:
    """(TIFF type, count, little-endian bytes) of a carried tag's value."""
    tag = TAGS[name]
    if tag.kind == "text":
        data = str(value).encode("utf-8") + b"\0"
        return 2, len(data), data
    if tag.kind == "ratio":
        return 5, 1, struct.pack("<II", *rational(Fraction(value)))
    return tag.type, 1, struct.pack("<I" if tag.type == 4 else "<H", int(value))


def ifd_bytes(entries: list[tuple[int, int, int, bytes]], at: int, big: bool = False) -> bytes:
    """One little-endian IFD at offset ``at`` of its TIFF structure (``entries``: tag, type, count, value bytes),
    its values longer than its value field after it (each at an even offset), and no next IFD. ``big``: a BigTIFF's
    IFD (an 8-byte entry count, 20-byte entries, 8-byte value fields and offsets), else a classic TIFF's."""
    entries = sorted(entries)
    head, entry, inline = ("<Q", "<HHQ", 8) if big else ("<H", "<HHI", 4)
    data_at = at + struct.calcsize(head) + (struct.calcsize(entry) + inline) * len(entries) + inline
    fields, data = [], b""
    for number, kind, count, value in entries:
        if len(value) <= inline:
            field = value.ljust(inline, b"\0")
        else:
            field = struct.pack("<Q" if big else "<I", data_at + len(data))
            data += value + b"\0" * (len(value) % 2)
        fields.append(struct.pack(entry, number, kind, count) + field)
    return struct.pack(head, len(entries)) + b"".join(fields) + b"\0" * inline + data


def exif_ifd(tags: dict, at: int, extra=(), big: bool = False) -> bytes:
    """The Exif IFD of ``tags`` (those of the Exif IFD, with ExifVersion 0232, and the raw ``extra`` entries) at
    offset ``at`` (of a BigTIFF where ``big``)."""
    entries = [(TAGS[n].tag, *encode(n, v)) for n, v in tags.items() if TAGS[n].ifd == "exif"]
    return ifd_bytes(entries + [(EXIF_VERSION, 7, 4, b"0232"), *extra], at, big)


def build(tags: dict, first_extra=(), exif_extra=()) -> bytes:
    """A whole little-endian Exif block (``II*``, the first IFD, then the Exif IFD) of ``tags`` and the raw entries
    ``first_extra`` and ``exif_extra`` (tag, type, count, bytes); Orientation 1 unless ``tags`` says otherwise."""
    tags = {"Orientation": 1, **tags}
    first = [(TAGS[n].tag, *encode(n, v)) for n, v in tags.items() if TAGS[n].ifd == "0"] + list(first_extra)
    size = len(ifd_bytes(first + [(EXIF_POINTER, 4, 1, b"\0" * 4)], 8))
    at = 8 + size + size % 2
    head = ifd_bytes(first + [(EXIF_POINTER, 4, 1, struct.pack("<I", at))], 8)
    return b"II*\0" + struct.pack("<I", 8) + head + b"\0" * (size % 2) + exif_ifd(tags, at, exif_extra)
