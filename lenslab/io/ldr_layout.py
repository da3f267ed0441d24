"""JPEG and PNG layouts read before a decoder sees the file: the declared size against the coded data.

JPEG (ITU T.81): the markers up to the first start of scan give the frame (``SOFn``: height, width,
components; ``SOF9``..``SOF15`` arithmetic-coded); every 8 x 8 block of a Huffman-coded scan costs at
least one bit (its DC difference), so a scan holding fewer bytes than ``blocks / 8`` cannot be real.
PNG (ISO 15948): ``IHDR`` gives the size, bit depth and colour type; the ``IDAT`` chunks hold a zlib
stream of ``height * (1 + row bytes)`` bytes, and Deflate expands at most 1032 times.
"""

from __future__ import annotations

import os

from lenslab.errors import FormatError
from lenslab.inputs.limits import check_size

_HEAD = 1 << 20
#: Deflate's best ratio (258-byte matches coded in 2 bits: 1032:1), with the zlib framing
PNG_MAX_RATIO = 1100
#: PNG colour type -> decoded channels (palette decodes to RGB or RGBA)
_PNG_CHANNELS = {0: 1, 2: 3, 3: 4, 4: 2, 6: 4}
_PNG_SAMPLES = {0: 1, 2: 3, 3: 1, 4: 2, 6: 4}


def declare_jpg(path, **_):
    from lenslab.io.budget import Declared

    size = os.path.getsize(path)
    with open(path, "rb") as f:
        data = f.read(_HEAD)
    pos, n, frame = 2, len(data), None
    while pos + 4 <= n:
        if data[pos] != 0xFF:
            raise FormatError(f"{path}: the JPG's marker at byte {pos} is damaged")
        marker = data[pos + 1]
        if marker == 0xFF:
            pos += 1
            continue
        if marker in (0x01,) or 0xD0 <= marker <= 0xD7:
            pos += 2
            continue
        length = int.from_bytes(data[pos + 2:pos + 4], "big")
        if length < 2:
            raise FormatError(f"{path}: the JPG's segment at byte {pos} has length {length}; the file is damaged")
        if 0xC0 <= marker <= 0xCF and marker not in (0xC4, 0xC8, 0xCC) and frame is None:
            if pos + 10 > n:
                break
            h = int.from_bytes(data[pos + 5:pos + 7], "big")
            w = int.from_bytes(data[pos + 7:pos + 9], "big")
            frame = (w, h, data[pos + 9], marker >= 0xC9)
        if marker == 0xDA:  # start of scan: the coded data follows
            if frame is None:
                break
            w, h, comps, arithmetic = frame
            if w == 0 or h == 0:
                raise FormatError(f"{path}: the JPG declares a size of {w} x {h} (a height set by a later DNL "
                                  "marker is not supported)")
            blocks = -(-w // 8) * -(-h // 8)
            return Declared(w, h, 3 if comps >= 3 else 1, min_bytes=0 if arithmetic else blocks // 8,
                            held=size - (pos + 2 + length), what="scan data (one bit per 8 x 8 block)",
                            extra_bytes=_gain_map_bytes(path, data, size, w, h))
        pos += 2 + length
    raise FormatError(f"{path}: the JPG has no frame header and scan in its first {min(n, _HEAD)} bytes; the "
                      "header is missing or damaged")


def _gain_map_bytes(path, head: bytes, size: int, width: int, height: int) -> int:
    """The float bytes of an Ultra HDR gain map the MPF index points to (0 for none, or one larger than the
    base image, which the reader does not decode: :mod:`lenslab.io.gainmap`)."""
    from lenslab.io.gainmap import declared

    def read_at(offset: int, n: int) -> bytes:
        with open(path, "rb") as f:
            f.seek(offset)
            return f.read(n)

    found = declared(head, size, read_at)
    if found is None or found[0] > width or found[1] > height:
        return 0
    return found[0] * found[1] * found[2] * 4


def declare_png(path, **_):
    from lenslab.io.budget import Declared

    size = os.path.getsize(path)
    with open(path, "rb") as f:
        head = f.read(33)
        if len(head) < 24 or head[12:16] != b"IHDR":
            raise FormatError(f"{path}: the PNG header is missing or damaged")
        w, h = int.from_bytes(head[16:20], "big"), int.from_bytes(head[20:24], "big")
        check_size(path, w, h)
        if len(head) < 26:
            raise FormatError(f"{path}: the PNG header is cut short; the file is truncated")
        bits, colour = head[24], head[25]
        if colour not in _PNG_CHANNELS or bits not in (1, 2, 4, 8, 16):
            raise FormatError(f"{path}: the PNG declares colour type {colour} with {bits} bits; it is damaged")
        idat, pos, chunks = 0, 8, 0
        while pos + 8 <= size:
            f.seek(pos)
            hdr = f.read(8)
            length, kind = int.from_bytes(hdr[:4], "big"), hdr[4:8]
            if length > 0x7FFFFFFF or pos + 12 + length > size:  # OpenCV would allocate the declared length
                raise FormatError(f"{path}: the PNG chunk {kind!r} at byte {pos} declares {length} bytes; the file "
                                  f"holds {size - pos - 12} after it; it is truncated or damaged")
            if kind == b"IDAT":
                idat += length
            if kind == b"IEND":
                break
            pos += 12 + length
            chunks += 1
            if chunks > 1 << 20:
                raise FormatError(f"{path}: the PNG holds more than {1 << 20} chunks; it is damaged or hostile")
    row = -(-w * _PNG_SAMPLES[colour] * bits // 8) + 1
    raw = row * h  # (an interlaced image holds a little more)
    return Declared(w, h, _PNG_CHANNELS[colour], min_bytes=raw // PNG_MAX_RATIO, held=idat,
                    what="compressed IDAT data")


# -- the JPG and PNG plugins' hooks (lenslab.io.formats.jpg, .png): the codec, lenslab.io.ldr, loads on first use --
def _read(path, selector=None, raw=False, *, kind):
    from lenslab.io.ldr import read_ldr

    return read_ldr(path, kind, raw=raw, selector=selector)


def _write(tmp, image, *, kind, **options):
    from lenslab.io.ldr import encode_ldr

    tmp.write_bytes(encode_ldr(image, kind, **options))
