"""Where an ICC profile sits in a PNG (the ``iCCP`` chunk, PNG Specification 11.3.2.3: a name, a NUL, method 0
and the zlib-compressed profile) and in a JPEG (``APP2`` segments that start ``ICC_PROFILE\\0``, a sequence
number and a count, ICC.1 Annex B.4): taken out for reading, put in for writing. Bounded by what the file holds
and by :data:`lenslab.io.colour.icc.MAX_BYTES` after inflation (a small chunk cannot inflate past it)."""

from __future__ import annotations

import struct
import zlib

from lenslab.io.colour.icc import MAX_BYTES, refuse

JPEG_TAG = b"ICC_PROFILE\0"
#: profile bytes in one APP2 segment: 65535 less its length field, tag, sequence number and count
JPEG_SEGMENT = 65535 - 2 - len(JPEG_TAG) - 2


def png_profile(png: bytes, where: str) -> bytes | None:
    """The profile of a PNG's ``iCCP`` chunk, inflated, or None without one."""
    from lenslab.io.colour.png_cicp import chunk_before_data

    chunk = chunk_before_data(png, b"iCCP")
    if chunk is None:
        return None
    end = chunk.find(b"\0", 0, 80)
    if end < 1 or len(chunk) < end + 2 or chunk[end + 1] != 0:
        refuse(where, "chunk iCCP is damaged (its name or compression method)")
    inflate = zlib.decompressobj()
    try:
        data = inflate.decompress(chunk[end + 2:], MAX_BYTES + 1)
    except zlib.error as exc:
        refuse(where, f"does not inflate ({exc})")
    if len(data) > MAX_BYTES:
        refuse(where, f"inflates past the {MAX_BYTES >> 20} MiB a profile is read up to")
    return data


def jpeg_profile(jpg: bytes, where: str) -> bytes | None:
    """The profile of a JPEG's ``APP2 ICC_PROFILE`` segments (before its scan), joined in sequence, or None."""
    parts: dict[int, bytes] = {}
    counts = set()
    pos, n, total = 2, len(jpg), 0
    while pos + 4 <= n and jpg[pos] == 0xFF:
        marker = jpg[pos + 1]
        if marker == 0xFF or 0xD0 <= marker <= 0xD7 or marker == 0x01:
            pos += 1 if marker == 0xFF else 2
            continue
        if marker == 0xDA:  # start of scan: metadata lies before it
            break
        length = int.from_bytes(jpg[pos + 2:pos + 4], "big")
        segment = jpg[pos + 4:pos + 2 + length]
        if marker == 0xE2 and segment.startswith(JPEG_TAG) and len(segment) >= len(JPEG_TAG) + 2:
            seq, count = segment[len(JPEG_TAG)], segment[len(JPEG_TAG) + 1]
            parts.setdefault(seq, segment[len(JPEG_TAG) + 2:])
            counts.add(count)
            total += length
            if total > MAX_BYTES:
                refuse(where, f"is more than the {MAX_BYTES >> 20} MiB a profile is read up to")
        pos += 2 + length
    if not parts:
        return None
    count = max(counts)
    if len(counts) != 1 or sorted(parts) != list(range(1, count + 1)):
        refuse(where, f"is split into {count} APP2 segments, and segments {sorted(parts)} are present")
    return b"".join(parts[i] for i in range(1, count + 1))


def png_with_profile(png: bytes, profile: bytes, name: bytes = b"ICC profile") -> bytes:
    """``png`` with an ``iCCP`` chunk of ``profile`` right after its ``IHDR`` (before ``cICP``, ``PLTE`` and
    the image data, as the chunk must be)."""
    from lenslab.io.colour.png_cicp import after_ihdr

    return after_ihdr(png, b"iCCP", name[:79] + b"\0\0" + zlib.compress(bytes(profile), 9))


def jpeg_with_profile(jpg: bytes, profile: bytes) -> bytes:
    """``jpg`` with ``profile`` in ``APP2 ICC_PROFILE`` segments after its start and its ``APP0`` (JFIF)."""
    profile = bytes(profile)
    pieces = [profile[i:i + JPEG_SEGMENT] for i in range(0, len(profile), JPEG_SEGMENT)] or [b""]
    if len(pieces) > 255:
        raise ValueError(f"an ICC profile of {len(profile)} bytes does not fit in 255 APP2 segments")
    app2 = b"".join(b"\xff\xe2" + struct.pack(">H", 2 + len(JPEG_TAG) + 2 + len(p)) + JPEG_TAG
                    + bytes([i + 1, len(pieces)]) + p for i, p in enumerate(pieces))
    at = 2
    if jpg[2:4] == b"\xff\xe0":  # keep JFIF's APP0 first, as its specification asks
        at = 4 + int.from_bytes(jpg[4:6], "big")
    return bytes(jpg[:at]) + app2 + bytes(jpg[at:])
