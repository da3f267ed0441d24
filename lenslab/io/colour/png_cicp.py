"""PNG's ``cICP`` chunk (PNG Specification, Third Edition, 11.3.2.6): the coding-independent code points of ITU-T
H.273 that tell a reader how the samples are encoded, written for HDR displays and read back.

Rec.2100 PQ is colour primaries 9 (BT.2020), transfer 16 (SMPTE ST 2084), matrix 0 (RGB), full range 1;
Rec.2100 HLG the same with transfer 18 (ARIB STD-B67); a PQ display on P3-D65 primaries has primaries 12, and
so has the SDR Display P3 (transfer 13, sRGB: without the chunk every reader takes its codes for sRGB on
Rec.709). The chunk is four bytes and must come before ``PLTE`` and ``IDAT``: it is written right after ``IHDR``.

Reading: a PQ or HLG PNG becomes linear Rec.709 light as a PQ or HLG video does (H.273's code points are
FFmpeg's, so :func:`lenslab.io.video.to_linear` decodes both: 1.0 = 203 cd/m², BT.2020 primaries and P3-D65
primaries converted); sRGB and BT.709 transfers (BT.601's and BT.2020's are the same curve) are decoded as
sRGB, as PNGs without the chunk are, then converted from P3-D65 or BT.2020 primaries to Rec.709 by
colour-science's matrix; any other transfer is left as code values, with a note.
"""

from __future__ import annotations

import struct
import zlib

PQ = (9, 16, 0, 1)
HLG = (9, 18, 0, 1)
BT709 = 1  # H.273 colour primaries of Rec.709 and sRGB
#: H.273 transfer characteristics a reader here names (others are reported by number)
TRANSFERS = {1: "BT.709", 6: "BT.601", 8: "linear", 13: "sRGB", 14: "BT.2020 (10-bit)", 15: "BT.2020 (12-bit)",
             16: "PQ (SMPTE ST 2084)", 18: "HLG (ARIB STD-B67)"}
#: what lenslab's sRGB decoding stands for: sRGB (13) and BT.709's curve (its usual stand-in), which H.273 gives
#: BT.709 (1), BT.601 (6) and BT.2020 at 10 and 12 bits (14, 15) alike
SRGB_TRANSFERS = (1, 6, 13, 14, 15)


def display_code_points(display: str) -> tuple[int, int, int, int] | None:
    """The cICP code points of an OpenColorIO display whose codes a reader would otherwise take for sRGB
    on Rec.709 primaries: a PQ or HLG display, or an SDR display on other primaries (``Display P3``: P3-D65,
    12, sRGB transfer, 13); None for the others. The primaries and transfer of its video tags
    (:data:`lenslab.io.video.colour.DISPLAY_TAGS`: ``ST2084-P3-D65`` is P3-D65, 12), RGB (matrix 0), full
    range; a display of another config named for PQ or HLG is taken as Rec.2100 (BT.2020 primaries), or
    P3-D65 when its name says P3."""
    from lenslab.io.video.colour import DISPLAY_TAGS

    low = display.lower()
    tags = DISPLAY_TAGS.get(low.split(" - display")[0])
    if tags is not None:
        return (tags[0], tags[1], 0, 1) if tags[1] in (PQ[1], HLG[1]) or tags[0] != BT709 else None
    transfer = HLG[1] if "hlg" in low else PQ[1] if ("pq" in low or "st2084" in low or "st-2084" in low) else None
    if transfer is None:
        return None
    return (12 if "p3" in low else 9, transfer, 0, 1)


def png_chunk(kind: bytes, data: bytes) -> bytes:
    """One PNG chunk: its length, type, data and CRC-32 (PNG Specification, 5.3)."""
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)


#: where the chunk after ``IHDR`` starts: the signature, IHDR's length and type, its 13 bytes and its CRC
IHDR_END = 8 + 8 + 13 + 4


def after_ihdr(png: bytes, kind: bytes, data: bytes) -> bytes:
    """``png`` with a chunk of ``kind`` holding ``data`` right after its ``IHDR`` (where ``cICP`` and ``iCCP``
    must come: before ``PLTE`` and the image data)."""
    if png[12:16] != b"IHDR":
        raise ValueError("not a PNG stream that starts with IHDR")
    return bytes(png[:IHDR_END]) + png_chunk(kind, data) + bytes(png[IHDR_END:])


def with_cicp(png: bytes, points) -> bytes:
    """``png`` with a ``cICP`` chunk of ``points`` (4 integers 0..255) right after its ``IHDR``."""
    points = tuple(int(v) for v in points)
    if len(points) != 4 or not all(0 <= v <= 255 for v in points):
        raise ValueError(f"cICP takes 4 code points 0..255, not {points!r}")
    return after_ihdr(png, b"cICP", bytes(points))


def chunk_before_data(png: bytes, kind: bytes) -> bytes | None:
    """The data of the first chunk of ``kind`` before the image data (``IDAT``), whole, or None."""
    pos, n = 8, len(png)
    while pos + 8 <= n:
        length = int.from_bytes(png[pos:pos + 4], "big")
        found = png[pos + 4:pos + 8]
        if found in (b"IDAT", b"IEND"):
            return None
        if found == kind and pos + 8 + length <= n:
            return png[pos + 8:pos + 8 + length]
        pos += 12 + length
    return None


def read_cicp(png: bytes) -> tuple[int, int, int, int] | None:
    """The code points of the first ``cICP`` chunk before the image data, or None."""
    data = chunk_before_data(png, b"cICP")
    return tuple(data) if data is not None and len(data) == 4 else None


#: pixels of a band that goes through colour-science's curves at once (they work in float64, with temporaries)
BAND_PIXELS = 1 << 14


def to_linear_light(codes, points, source: str = "the PNG's cICP chunk", maxval: int | None = None):
    """(image, note) for ``codes`` (H x W x C code values in [0, 1], or integer codes over ``maxval``; alpha last for
    C = 2, 4) of a file whose code ``points`` (named ``source`` in the note) have a transfer that is not sRGB: PQ
    and HLG as linear Rec.709 light (float32), anything else unchanged (integer codes: over ``maxval``). Integer
    codes go to the curve in float64 a band of rows at a time, so the read holds no float64 image."""
    from fractions import Fraction

    import numpy as np

    primaries, transfer, matrix, full = points
    scale = 1.0 if maxval is None else float(maxval)
    c = codes.shape[2]
    if transfer not in (16, 18):
        note = f"{source} says {describe(points)}: read as its code values, not decoded"
        return (codes if maxval is None else (codes / scale).astype(np.float32)), note
    from lenslab.io.video import REFERENCE_WHITE, VideoInfo, to_linear

    colour = c - 1 if c in (2, 4) else c
    info = VideoInfo(codes.shape[1], codes.shape[0], Fraction(1), 1, "png", "rgb48", primaries=primaries if colour == 3
                     else 2, transfer=transfer, matrix=matrix, range=full)  # grey: no primaries to convert
    out = np.empty(codes.shape, np.float32)
    if colour < c:
        out[..., colour:] = codes[..., colour:] / scale
    rows = max(1, BAND_PIXELS // max(1, codes.shape[1]))
    for r0 in range(0, codes.shape[0], rows):  # (each pixel's light depends on its own codes alone)
        out[r0:r0 + rows, :, :colour] = to_linear(codes[r0:r0 + rows, :, :colour] / scale, info)
    what = "PQ" if transfer == 16 else "HLG"
    return out, f"{what} decoded to linear Rec.709 light, 1.0 = {REFERENCE_WHITE:g} cd/m2 ({source})"


#: the names notes give the H.273 primaries converted to Rec.709
H273_NAMES = {12: "P3-D65", 9: "BT.2020"}


def wide_to_709(image, primaries: int, source: str = "the PNG's cICP chunk") -> str:
    """Linear light decoded from sRGB codes on H.273 ``primaries`` (H x W x C float32, straight colour, alpha
    last for C = 4) -> Rec.709 primaries in place, by colour-science's matrix
    (:func:`lenslab.io.colour.primaries.h273_matrix`); the note a reader shows. Rec.709 primaries, and
    primaries lenslab reads as Rec.709, are left alone."""
    from lenslab.io.colour.primaries import h273_matrix, to_rec709

    matrix = h273_matrix(primaries)
    if matrix is None:
        return f"{source} says primaries {primaries}: read as Rec.709"
    to_rec709(image, matrix)
    name = H273_NAMES.get(int(primaries), f"primaries {primaries}")
    return f"sRGB codes on {name} primaries ({source}), converted to Rec.709"


def describe(points) -> str:
    """``"primaries 9, transfer 16 PQ (SMPTE ST 2084), matrix 0, full range"`` for a note."""
    p, t, m, full = points
    name = TRANSFERS.get(t)
    return (f"primaries {p}, transfer {t}{' ' + name if name else ''}, matrix {m}, "
            f"{'full' if full else 'narrow'} range")
