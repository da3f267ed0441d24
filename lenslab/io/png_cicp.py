"""PNG's ``cICP`` chunk (PNG Specification, Third Edition, 11.3.2.6): the coding-independent code points of
ITU-T H.273 that tell a reader how the samples are encoded, written for HDR displays and read back.

Rec.2100 PQ is colour primaries 9 (BT.2020), transfer 16 (SMPTE ST 2084), matrix 0 (RGB), full range 1;
Rec.2100 HLG the same with transfer 18 (ARIB STD-B67). The chunk is four bytes and must come before
``PLTE`` and ``IDAT``: it is written right after ``IHDR``.
"""

from __future__ import annotations

import struct
import zlib

PQ = (9, 16, 0, 1)
HLG = (9, 18, 0, 1)
#: H.273 transfer characteristics a reader here names (others are reported by number)
TRANSFERS = {1: "BT.709", 8: "linear", 13: "sRGB", 14: "BT.2020 (10-bit)", 15: "BT.2020 (12-bit)",
             16: "PQ (SMPTE ST 2084)", 18: "HLG (ARIB STD-B67)"}
SRGB_TRANSFERS = (1, 13)  # what lenslab's sRGB decoding stands for (BT.709's curve is its usual stand-in)


def display_code_points(display: str) -> tuple[int, int, int, int] | None:
    """The cICP code points of an OpenColorIO display name: Rec.2100 PQ or HLG, else None."""
    low = display.lower()
    if "hlg" in low:
        return HLG
    if "pq" in low or "st2084" in low or "st-2084" in low:
        return PQ
    return None


def _chunk(kind: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)


def with_cicp(png: bytes, points) -> bytes:
    """``png`` with a ``cICP`` chunk of ``points`` (4 integers 0..255) right after its ``IHDR``."""
    points = tuple(int(v) for v in points)
    if len(points) != 4 or not all(0 <= v <= 255 for v in points):
        raise ValueError(f"cICP takes 4 code points 0..255, not {points!r}")
    end = 8 + 8 + 13 + 4  # signature, IHDR length and type, its 13 bytes, its CRC
    if png[12:16] != b"IHDR":
        raise ValueError("not a PNG stream that starts with IHDR")
    return png[:end] + _chunk(b"cICP", bytes(points)) + png[end:]


def read_cicp(png: bytes) -> tuple[int, int, int, int] | None:
    """The code points of the first ``cICP`` chunk before the image data, or None."""
    pos, n = 8, len(png)
    while pos + 8 <= n:
        length = int.from_bytes(png[pos:pos + 4], "big")
        kind = png[pos + 4:pos + 8]
        if kind in (b"IDAT", b"IEND"):
            return None
        if kind == b"cICP" and length == 4 and pos + 12 <= n:
            return tuple(png[pos + 8:pos + 12])
        pos += 12 + length
    return None


def describe(points) -> str:
    """``"primaries 9, transfer 16 PQ (SMPTE ST 2084), matrix 0, full range"`` for a note."""
    p, t, m, full = points
    name = TRANSFERS.get(t)
    return (f"primaries {p}, transfer {t}{' ' + name if name else ''}, matrix {m}, "
            f"{'full' if full else 'narrow'} range")
