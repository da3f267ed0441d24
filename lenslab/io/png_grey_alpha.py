"""Grey and alpha PNGs (colour type 4, PNG Specification 11.2.2), which OpenCV neither keeps nor writes.

OpenCV decodes a grey+alpha PNG to four channels (the grey repeated as B, G, R) and encodes only 1, 3 or
4 channels. Reading keeps the grey and the alpha (two channels, as OpenImageIO and tifffile name them
``Y, A``); writing makes the file here: ``IHDR`` (colour type 4, bit depth 8 or 16), one ``IDAT`` of the
zlib-compressed scanlines (each row preceded by its filter byte, 0: None; samples big-endian) and ``IEND``.
"""

from __future__ import annotations

import struct
import zlib

import numpy as np

from lenslab.io.colour.png_cicp import png_chunk

SIGNATURE = b"\x89PNG\r\n\x1a\n"
GREY_ALPHA = 4  # IHDR colour type


def is_grey_alpha(png: bytes) -> bool:
    """Whether the PNG's ``IHDR`` declares grey and alpha (colour type 4)."""
    return len(png) > 25 and png[12:16] == b"IHDR" and png[25] == GREY_ALPHA


def encode_grey_alpha(codes: np.ndarray, compression: int = 1) -> bytes:
    """A PNG of ``codes`` (uint8 or uint16 ``H x W x 2``: grey, then straight alpha)."""
    h, w, c = codes.shape
    if c != 2 or codes.dtype not in (np.uint8, np.uint16):
        raise ValueError(f"grey+alpha PNG takes uint8/uint16 H x W x 2 samples, not {codes.dtype} x {c}")
    depth = codes.dtype.itemsize * 8
    rows = np.ascontiguousarray(codes, dtype=codes.dtype.newbyteorder(">")).view(np.uint8).reshape(h, -1)
    raw = np.concatenate([np.zeros((h, 1), np.uint8), rows], axis=1)  # filter byte 0 on each row
    head = struct.pack(">IIBBBBB", w, h, depth, GREY_ALPHA, 0, 0, 0)
    return (SIGNATURE + png_chunk(b"IHDR", head) + png_chunk(b"IDAT", zlib.compress(raw.tobytes(), int(compression)))
            + png_chunk(b"IEND", b""))
