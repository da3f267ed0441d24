"""Where an Ultra HDR JPEG keeps its gain map: the Multi-Picture Format index (CIPA DC-007) and the XMP packets.

Every offset and length is checked against the bytes at hand before it is used: a hostile file gets a
:class:`ContainerError` (one line, which the reader turns into a note), never an out-of-range slice or a
large allocation.

- :func:`segments` walks a JPEG's marker segments (ITU T.81 B.1.1.2) up to its first start of scan.
- :func:`mpf_images` reads the MP Index IFD of the ``APP2`` segment starting ``MPF\\0`` (CIPA DC-007, 5.2): a
  TIFF header whose offsets count from the byte after ``MPF\\0``, the ``MPEntry`` tag (0xB002) holding one
  16-byte entry per image (attribute, size, offset, two dependent-image entry numbers); the first image's
  offset is 0 (it starts the file).
- :func:`xmp` gives the standard XMP packet of an ``APP1`` segment (XMP Part 3, 1.1.3); extended XMP is not
  read (Ultra HDR keeps no gain map metadata there).
"""

from __future__ import annotations

XMP_SIGNATURE = b"http://ns.adobe.com/xap/1.0/\x00"
MPF_SIGNATURE = b"MPF\x00"
ISO_SIGNATURE = b"urn:iso:std:iso:ts:21496:-1\x00"
#: the MPF ``MPEntry`` tag and the most entries read (a phone writes 2 or 3)
MP_ENTRY, MAX_ENTRIES = 0xB002, 64


class ContainerError(ValueError):
    """The MPF index or a segment is damaged: what is wrong, in words."""


def segments(data: bytes | memoryview, start: int = 0):
    """``(marker, payload_start, payload_end)`` of each segment from the SOI at ``start`` up to the first
    start of scan (``0xDA``, the last given: the coded data follows its end); stops quietly at a damaged or cut
    segment."""
    n = len(data)
    if data[start:start + 2] != b"\xff\xd8":
        raise ContainerError("it does not start with a JPEG start-of-image marker")
    pos = start + 2
    while pos + 4 <= n:
        if data[pos] != 0xFF:
            return
        marker = data[pos + 1]
        if marker == 0xFF:
            pos += 1
            continue
        if marker == 0x01 or 0xD0 <= marker <= 0xD7:
            pos += 2
            continue
        length = int.from_bytes(data[pos + 2:pos + 4], "big")
        if length < 2 or pos + 2 + length > n:
            return
        yield marker, pos + 4, pos + 2 + length
        if marker == 0xDA:
            return
        pos += 2 + length


def payloads(data, marker: int, signature: bytes, start: int = 0) -> list[bytes]:
    """The payloads (after ``signature``) of the segments ``marker`` that begin with ``signature``."""
    out = []
    for m, a, b in segments(data, start):
        if m == marker and bytes(data[a:a + len(signature)]) == signature:
            out.append(bytes(data[a + len(signature):b]))
    return out


def xmp(data, start: int = 0) -> bytes | None:
    """The first standard XMP packet of the JPEG at ``start``, or None."""
    found = payloads(data, 0xE1, XMP_SIGNATURE, start)
    return found[0] if found else None


def frame(data, start: int = 0) -> tuple[int, int, int, bool, int] | None:
    """Width, height, components, arithmetic coding and the end of the first scan header of the JPEG at
    ``start`` (ITU T.81 B.2.2, B.2.3), or None when its segments up to the first scan do not hold both."""
    found = None
    for m, a, b in segments(data, start):
        if 0xC0 <= m <= 0xCF and m not in (0xC4, 0xC8, 0xCC) and found is None and b - a >= 6:
            found = (int.from_bytes(data[a + 3:a + 5], "big"), int.from_bytes(data[a + 1:a + 3], "big"), data[a + 5],
                     m >= 0xC9)
        if m == 0xDA:
            return None if found is None else (*found, b)
    return None


def mpf_images(data, total: int | None = None) -> list[tuple[int, int]] | None:
    """``(offset in the file, size)`` of every image the MPF index lists, checked to lie inside the file
    (``total`` bytes; ``len(data)`` when None: ``data`` is then the whole file); None when the file has no MPF
    segment. Raises :class:`ContainerError` for a damaged index."""
    n = len(data) if total is None else total
    for m, a, b in segments(data):
        if m != 0xE2 or bytes(data[a:a + 4]) != MPF_SIGNATURE:
            continue
        base = a + 4  # MPF offsets count from the TIFF header
        tiff = bytes(data[base:b])
        order = {b"II*\x00": "little", b"MM\x00*": "big"}.get(tiff[:4])
        if order is None:
            raise ContainerError("its MPF index has no TIFF header")

        def u(at: int, size: int) -> int:
            if at < 0 or at + size > len(tiff):
                raise ContainerError("its MPF index points outside its segment")
            return int.from_bytes(tiff[at:at + size], order)

        ifd = u(4, 4)
        entries = None
        for i in range(min(u(ifd, 2), 256)):
            tag, kind, count, value = u(ifd + 2 + 12 * i, 2), u(ifd + 4 + 12 * i, 2), u(ifd + 6 + 12 * i, 4), \
                u(ifd + 10 + 12 * i, 4)
            if tag == MP_ENTRY:
                if kind != 7 or count % 16 or not 16 <= count <= 16 * MAX_ENTRIES:
                    raise ContainerError(f"its MPF image list has {count} bytes, not 16 a picture")
                entries = [(u(value + 16 * k + 4, 4), u(value + 16 * k + 8, 4)) for k in range(count // 16)]
        if entries is None:
            raise ContainerError("its MPF index lists no images")
        out = []
        for k, (size, offset) in enumerate(entries):
            at = 0 if k == 0 else base + offset
            if k and (offset == 0 or at + size > n or size < 4):
                raise ContainerError(f"its MPF index puts picture {k + 1} at bytes {at}..{at + size}, outside the "
                                     f"file's {n} bytes")
            out.append((at, size))
        return out
    return None
