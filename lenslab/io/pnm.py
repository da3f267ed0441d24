"""Netpbm PPM/PGM/PBM: P1..P6, maxval 1..65535 (16-bit samples big-endian), comments in the header.

Samples are scaled by their maxval to [0, 1] whatever it is (so a maxval-1023 file reads the same as
an 8-bit one), then decoded from sRGB to linear light unless ``raw=True``. PBM (P1, P4) is 1 = black.
Every size in the header is checked against the bytes actually present before anything is allocated.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from lenslab.errors import FormatError
from lenslab.inputs.limits import check_size

_WS = b" \t\r\n\x0b\x0c"
_KIND = {b"P1": ("pbm", 1, False), b"P2": ("pgm", 1, False), b"P3": ("ppm", 3, False),
         b"P4": ("pbm", 1, True), b"P5": ("pgm", 1, True), b"P6": ("ppm", 3, True)}
_MAX_DIGITS = 9  # larger numbers cannot be a valid size or maxval
_COMMENT = re.compile(rb"#[^\r\n]*")


def _header(path, data: bytes, count: int) -> tuple[list[int], int]:
    """Parse the magic and ``count`` decimal fields; return (fields, offset just past the last one)."""
    pos, n = 2, len(data)
    fields: list[int] = []
    while len(fields) < count:
        while pos < n:  # skip white space and comments
            c = data[pos]
            if c in _WS:
                pos += 1
            elif c == 0x23:  # '#': comment to the end of the line
                while pos < n and data[pos] not in b"\r\n":
                    pos += 1
            else:
                break
        start = pos
        while pos < n and 0x30 <= data[pos] <= 0x39 and pos - start <= _MAX_DIGITS:
            pos += 1
        if pos == start:
            what = ("width", "height", "maxval")[len(fields)]
            if pos >= n:
                raise FormatError(f"{path}: the header ends before the {what}; the file is truncated")
            raise FormatError(f"{path}: expected the {what} in the header, found {data[pos:pos + 8]!r}")
        if pos - start > _MAX_DIGITS:
            raise FormatError(f"{path}: a header number has more than {_MAX_DIGITS} digits; the file is damaged")
        fields.append(int(data[start:pos]))
    return fields, pos


def read_pnm(path: Path, raw: bool = False) -> tuple[np.ndarray, dict]:
    data = path.read_bytes()
    magic = data[:2]
    if magic not in _KIND:
        raise FormatError(f"{path}: not a PNM file (magic {magic!r}; expected P1..P6)")
    fmt, channels, binary = _KIND[magic]
    bitmap = fmt == "pbm"
    (fields, pos) = _header(path, data, 2 if bitmap else 3)
    width, height = fields[0], fields[1]
    maxval = 1 if bitmap else fields[2]
    if not 1 <= maxval <= 65535:
        raise FormatError(f"{path}: maxval {maxval} is outside 1..65535; the file is damaged")
    check_size(path, width, height)
    if pos >= len(data) or data[pos] not in _WS:
        raise FormatError(f"{path}: the header must end with one white-space character; the file is "
                          "truncated or damaged")
    pos += 1
    n = width * height * channels
    if binary:
        if bitmap:
            row_bytes = (width + 7) // 8
            need = row_bytes * height
        else:
            itemsize = 1 if maxval < 256 else 2
            need = n * itemsize
        have = len(data) - pos
        if have < need:
            raise FormatError(f"{path}: the header announces {width} x {height} pixels ({need} bytes) but the "
                              f"file holds {have}; it is truncated")
        if bitmap:
            packed = np.frombuffer(data, np.uint8, need, pos).reshape(height, row_bytes)
            bits = np.unpackbits(packed, axis=1)[:, :width]
            codes = (1 - bits).reshape(height, width, 1)  # 1 = black
        else:
            dtype = np.dtype(">u2") if itemsize == 2 else np.dtype(np.uint8)
            codes = np.frombuffer(data, dtype, n, pos).reshape(height, width, channels)
    else:
        body = data[pos:]
        if b"#" in body:
            body = _COMMENT.sub(b" ", body)
        if bitmap:  # plain PBM: '0'/'1' characters, white space optional
            body = body.translate(None, _WS)
            if len(body) < n:
                raise FormatError(f"{path}: the header announces {n} pixels but the file holds {len(body)}; "
                                  "it is truncated")
            chars = np.frombuffer(body, np.uint8, n)
            if not np.all((chars == 0x30) | (chars == 0x31)):
                raise FormatError(f"{path}: plain PBM pixels must be '0' or '1'; the file is damaged")
            codes = (0x31 - chars).astype(np.uint8).reshape(height, width, 1)
        else:
            if len(body) < 2 * n - 1:  # every sample needs a digit and a separator
                raise FormatError(f"{path}: the header announces {n} samples but the file is too short to "
                                  "hold them; it is truncated")
            tokens = body.split()
            if len(tokens) < n:
                raise FormatError(f"{path}: the header announces {n} samples but the file holds "
                                  f"{len(tokens)}; it is truncated")
            if any(len(t) > 5 for t in tokens[:n]):
                raise FormatError(f"{path}: a sample has more than 5 digits; the file is damaged")
            try:
                codes = np.array(tokens[:n], dtype=np.int32).reshape(height, width, channels)
            except ValueError:
                raise FormatError(f"{path}: a sample is not a decimal number; the file is damaged") from None
    if not bitmap and int(codes.max(initial=0)) > maxval:
        raise FormatError(f"{path}: a sample exceeds the maxval {maxval}; the file is damaged")
    if raw:
        image = codes.astype(np.float32) / np.float32(maxval)
    else:
        from lenslab.io.encode import decode_srgb
        image = decode_srgb(codes.astype(np.intp, copy=False), maxval)
    bit_depth = 1 if bitmap else int(maxval).bit_length()
    meta = {
        "format": fmt,
        "bit_depth": bit_depth,
        "sample_type": "uint",
        "channels": ["R", "G", "B"] if channels == 3 else ["Y"],
        "display_encoded": not raw,
        "attributes": {"magic": magic.decode(), "maxval": maxval, "encoding": "binary" if binary else "ascii"},
    }
    return np.ascontiguousarray(image, dtype=np.float32), meta


def encode_pnm(image: np.ndarray, bits: int = 8, ascii: bool = False, raw: bool = False,
               dither: bool = False) -> bytes:
    """Encode a float image (C = 1 or 3) as P5/P6 (or P2/P3 with ``ascii=True``), 8 or 16 bits."""
    from lenslab.io.encode import encode_codes

    if bits not in (8, 16):
        raise FormatError(f"PPM/PGM can be written with bits=8 or bits=16, not {bits!r}")
    h, w, c = image.shape
    codes = encode_codes(image, bits, raw, dither)  # (counts the NaN and infinities it replaces)
    maxval = (1 << bits) - 1
    magic = {(1, False): b"P5", (3, False): b"P6", (1, True): b"P2", (3, True): b"P3"}[(c, bool(ascii))]
    header = b"%s\n%d %d\n%d\n" % (magic, w, h, maxval)
    if ascii:
        rows = [b" ".join(b"%d" % v for v in row) for row in codes.reshape(h, w * c).tolist()]
        return header + b"\n".join(rows) + b"\n"
    if bits == 16:
        codes = codes.astype(">u2")
    return header + codes.tobytes()


def declare_pnm(path, **_):
    """:class:`lenslab.io.budget.Declared` of a PNM: binary samples are counted exactly; a plain (text)
    file needs one byte per PBM pixel and two (a digit and a separator) per other sample."""
    import os

    from lenslab.io.budget import Declared

    with open(path, "rb") as f:
        data = f.read(4096)
    if data[:2] not in _KIND:
        raise FormatError(f"{path}: not a PNM file (magic {data[:2]!r}; expected P1..P6)")
    fmt, channels, binary = _KIND[data[:2]]
    fields, pos = _header(path, data, 2 if fmt == "pbm" else 3)
    width, height = fields[0], fields[1]
    maxval = 1 if fmt == "pbm" else fields[2]
    if fmt == "pbm":
        need = -(-width // 8) * height if binary else width * height
    else:
        need = width * height * channels * ((1 if maxval < 256 else 2) if binary else 2)
    return Declared(width, height, channels, min_bytes=need, held=os.path.getsize(path) - pos - 1,
                    what="samples")
