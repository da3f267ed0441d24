"""The TIFF structure of an Exif block (TIFF 6.0 section 2; CIPA DC-008): its carried tags read, and a block of them
built.

Reading goes through ``read(offset, n)`` over a block of ``size`` bytes (a JPEG's APP1 payload, a PNG's eXIf chunk,
a TIFF file itself) by :mod:`lenslab.io.tiff.walk`. Only the first IFD and the Exif IFD it points to are walked; every
offset and count is checked against ``size`` before it is followed, so a damaged or hostile block raises
:class:`Damaged` and never reads past its end nor loops.

>>> block = build({"Make": "Acme", "FocalLengthIn35mmFilm": 26})
>>> tags, odd = parse(lambda at, n: block[at:at + n], len(block))
>>> tags, odd
({'Make': 'Acme', 'Orientation': 1, 'FocalLengthIn35mmFilm': 26}, [])
"""

from __future__ import annotations

import struct
from fractions import Fraction

from lenslab.exif_tags import BY_NUMBER, EXIF_POINTER, EXIF_VERSION, TAGS, TEXT_MAX, checked
from lenslab.io.tiff.walk import CODES, SIZES, Outside, entries, header, value_bytes

#: the TIFF types each kind of tag is read from
#: (a rational also from FLOAT and DOUBLE, 11 and 12, as Pillow writes a float: written back as a RATIONAL)
READ_TYPES = {"text": (2,), "int": (1, 3, 4, 13), "ratio": (5, 10, 11, 12)}


class Damaged(ValueError):
    """An Exif block whose structure cannot be followed (a header, an IFD or a value beyond its end)."""


def _value(read, size: int, order: str, name: str, kind: int, count: int, field: bytes):
    """The checked value of carried tag ``name``, or None where its type or count is not one the tag takes."""
    tag = TAGS[name]
    if kind not in READ_TYPES[tag.kind] or count < 1 or (tag.kind == "text" and count > TEXT_MAX + 1):
        return None
    n = SIZES[kind] * (count if tag.kind == "text" else 1)  # (a number: its first value, as exiftool shows it)
    try:
        data = value_bytes(read, size, order, kind, count, field, n)
    except Outside as exc:
        raise Damaged(f"{name}'s value at byte {exc.args[1]} lies outside its {size} bytes") from None
    if tag.kind == "text":
        return checked(name, data)
    number = struct.unpack(order + CODES[kind], data)
    if kind in (5, 10):
        return checked(name, Fraction(*number)) if number[1] else None
    if kind == 11:  # (NaN and infinity: no value, as checked says)
        from lenslab.exif_tags import single_ratio

        return checked(name, single_ratio(number[0]))
    return checked(name, number[0])


def parse(read, size: int) -> tuple[dict, list[str]]:
    """(the carried tags the block holds, the names of those whose type, count or value is none the tag takes)."""
    found = header(read(0, 16) if size >= 16 else read(0, 8) if size >= 8 else b"")
    if found is None or not found.standard:
        raise Damaged("no TIFF header (II or MM, 42; or BigTIFF's 43)")
    order, big, tags, odd = found.order, found.big, {}, []
    ifds = [("0", found.first)]
    for ifd, at in ifds:
        try:
            walked = entries(read, size, at, order, big, lowest=16 if big else 4)[0]
        except Outside as exc:
            raise Damaged(f"an IFD at byte {at} lies outside its {size} bytes" if exc.args[2] is None else f"the IFD "
                          f"at byte {at} declares {exc.args[2]} entries, more than its {size} bytes hold") from None
        for number, kind, count, field in walked:
            wide = big and kind in (16, 18)  # (LONG8, IFD8: a BigTIFF's)
            if ifd == "0" and number == EXIF_POINTER and (kind in (4, 13) or wide) and count == 1 and len(ifds) == 1:
                ifds.append(("exif", struct.unpack(order + CODES[kind], field[:SIZES[kind]])[0]))  # (followed once)
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
