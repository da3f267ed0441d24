"""Radiance RGBE (``.hdr``, ``.pic``): the most common download format for HDR panoramas.

A text header (``#?RADIANCE`` or ``#?RGBE``, ``NAME=value`` lines, an empty line), a resolution line
such as ``-Y 512 +X 1024``, then scanlines of 4-byte pixels: a shared exponent ``E`` and three
mantissas. Scanlines are flat, run-length encoded the new way (``2 2 hi lo`` then each component run
length encoded on its own) or the old way (a pixel ``1 1 1 n`` repeats the previous one); files may
mix them.

Reading follows Radiance's own conversion (``colr_color`` in ``src/common/color.c``): a component is
``(m + 0.5) * 2**(E - 136)`` and 0 when ``E == 0``. OpenCV (Greg Ward's ``rgbe.c``) leaves out the
``+ 0.5``, so its values are up to half a mantissa step lower. ``EXPOSURE`` (product of every such
line) and ``COLORCORR`` (per channel) say by how much the stored values were multiplied; lenslab
divides them out, giving the original radiance (as Radiance's ``pvalue -o`` does), and reports them
in ``meta["attributes"]``. Every orientation of the resolution line (``-Y +X`` is the usual one, top
row first; ``+Y`` bottom first; ``-X`` right to left; ``X`` first: column order) is turned into rows
from the top, left to right. ``FORMAT=32-bit_rle_xyze`` files are refused: convert them to RGBE with
Radiance's ``ra_xyze -r`` first.

Writing: ``#?RADIANCE``, ``FORMAT=32-bit_rle_rgbe``, ``-Y H +X W``, new-style run-length encoded
scanlines (flat when the width is outside 8..32767, which the encoding cannot describe, or with
``rle=False``), each pixel from Radiance's ``setcolr``: ``E`` from ``frexp`` of the largest
component, mantissas truncated. Negative values and NaN become 0; grey is written as R = G = B.
"""

from __future__ import annotations

import math
import os
import re
from pathlib import Path

import numpy as np

from lenslab.errors import FormatError, clip
from lenslab.inputs.limits import check_size

_MAX_HEADER = 1 << 16
#: the smallest EXPOSURE or COLORCORR factor accepted (its inverse must stay a finite float32)
_MIN_FACTOR = 1e-30
_RES = re.compile(rb"^([+-])([XY]) +(\d+) +([+-])([XY]) +(\d+)$")


def parse_header(path, data: bytes) -> tuple[dict, tuple, int]:
    """(attributes, (sign1, axis1, n1, sign2, axis2, n2), offset of the pixel data)."""
    end = data.find(b"\n\n", 0, _MAX_HEADER)
    if end < 0:
        raise FormatError(f"{path}: the Radiance header has no end (no empty line); the file is damaged")
    lines = data[:end].split(b"\n")
    attrs: dict = {"exposure": 1.0, "colorcorr": [1.0, 1.0, 1.0], "format": "32-bit_rle_rgbe"}
    for line in lines[1:]:
        text = line.decode("latin-1").strip()
        if not text or text.startswith("#"):
            continue
        key, eq, value = text.partition("=")
        if not eq:
            attrs.setdefault("commands", []).append(text)  # the history of commands that made the file
            continue
        key, value = key.strip().upper(), value.strip()
        try:
            if key == "EXPOSURE":
                attrs["exposure"] *= float(value)
            elif key == "COLORCORR":
                factors = [float(v) for v in value.split()]
                attrs["colorcorr"] = [a * b for a, b in zip(attrs["colorcorr"], factors + [1.0] * 3)]
            elif key == "FORMAT":
                attrs["format"] = value
            else:
                attrs[key.lower()] = value
        except ValueError:
            raise FormatError(f"{path}: the header line {clip(text)} is not a valid number") from None
    if attrs["format"] == "32-bit_rle_xyze":
        raise FormatError(f"{path}: a Radiance XYZE file (CIE XYZ, not RGB); lenslab reads RGBE only: convert it "
                          "with Radiance's 'ra_xyze -r' first")
    if attrs["format"] != "32-bit_rle_rgbe":
        raise FormatError(f"{path}: unknown Radiance FORMAT {clip(attrs['format'])}; expected 32-bit_rle_rgbe")
    for name, values in (("EXPOSURE", [attrs["exposure"]]), ("COLORCORR", attrs["colorcorr"])):
        if not all(math.isfinite(v) and _MIN_FACTOR <= v <= 1 / _MIN_FACTOR for v in values):
            raise FormatError(f"{path}: {name} must be a finite positive factor in "
                              f"{_MIN_FACTOR:g}..{1 / _MIN_FACTOR:g}, "
                              f"got {' '.join(f'{v:g}' for v in values)[:40]}; the file is damaged")
    nl = data.find(b"\n", end + 2, end + 2 + 256)
    if nl < 0:
        raise FormatError(f"{path}: the resolution line after the header is missing; the file is truncated")
    m = _RES.match(data[end + 2:nl].strip())
    if m is None or m.group(2) == m.group(5):
        raise FormatError(f"{path}: the resolution line {data[end + 2:nl][:40]!r} is not like '-Y 512 +X 1024'")
    res = (m.group(1), m.group(2), int(m.group(3)), m.group(4), m.group(5), int(m.group(6)))
    return attrs, res, nl + 1


def _decode_kernel():
    import math

    import numba

    @numba.njit(cache=True, nogil=True)
    def decode(data, pos, rows, width, row, out):
        """RGBE bytes from ``pos`` -> ``out`` (rows x width x 3 float32), one scanline at a time through
        ``row`` (width x 4 uint8), with Radiance's ``(m + 0.5) * 2**(E - 136)``. Returns the scanlines
        decoded completely (fewer than ``rows``: the data ended early or is corrupt)."""
        n = data.size
        for y in range(rows):
            if (8 <= width <= 0x7FFF and pos + 4 <= n and data[pos] == 2 and data[pos + 1] == 2
                    and data[pos + 2] < 128):
                if (data[pos + 2] << 8 | data[pos + 3]) != width:
                    return y
                pos += 4
                for c in range(4):
                    x = 0
                    while x < width:
                        if pos >= n:
                            return y
                        count = data[pos]
                        pos += 1
                        if count > 128:
                            count -= 128
                            if x + count > width or pos >= n:
                                return y
                            v = data[pos]
                            pos += 1
                            for k in range(count):
                                row[x + k, c] = v
                        else:
                            if count == 0 or x + count > width or pos + count > n:
                                return y
                            for k in range(count):
                                row[x + k, c] = data[pos + k]
                            pos += count
                        x += count
            else:
                x = 0  # flat pixels, with old-style runs
                shift = 0
                while x < width:
                    if pos + 4 > n:
                        return y
                    if data[pos] == 1 and data[pos + 1] == 1 and data[pos + 2] == 1:
                        if shift > 16:
                            return y
                        count = data[pos + 3] << shift
                        pos += 4
                        if x == 0 or x + count > width:
                            return y
                        for k in range(count):
                            for c in range(4):
                                row[x + k, c] = row[x - 1, c]
                        x += count
                        shift += 8
                    else:
                        for c in range(4):
                            row[x, c] = data[pos + c]
                        pos += 4
                        x += 1
                        shift = 0
            for x in range(width):
                e = row[x, 3]
                if e == 0:
                    out[y, x, 0] = out[y, x, 1] = out[y, x, 2] = 0.0
                else:
                    f = math.ldexp(1.0, e - 136)
                    for c in range(3):
                        out[y, x, c] = (row[x, c] + 0.5) * f
        return rows

    return decode


_KERNELS: dict = {}


def _kernel(name: str, build):
    if name not in _KERNELS:
        _KERNELS[name] = build()
    return _KERNELS[name]


def _read_head(path: Path):
    """(attributes, resolution, pixel offset, file bytes or None) of a Radiance file, from its header."""
    with open(path, "rb") as f:
        data = f.read(_MAX_HEADER + 512)
    if not data.startswith(b"#?"):
        raise FormatError(f"{path}: not a Radiance file (it does not start with '#?')")
    return parse_header(path, data)


def declare_hdr(path, **_):
    """:class:`lenslab.io.budget.Declared` of a Radiance file: every scanline holds at least one 4-byte
    pixel and, when wider than one pixel, one 4-byte old-style run (the most compact encoding)."""
    from lenslab.io.budget import Declared

    _, (s1, a1, n1, s2, a2, n2), pos = _read_head(path)
    w, h = (n1, n2) if a1 == b"X" else (n2, n1)
    per_line = 4 if n2 == 1 else 8 if n2 <= 256 else 12
    return Declared(w, h, 3, min_bytes=n1 * per_line, held=os.path.getsize(path) - pos,
                    what="scanline data (4 bytes a pixel, old-style runs at best)")


def read_hdr(path: Path) -> tuple[np.ndarray, dict]:
    attrs, (s1, a1, n1, s2, a2, n2), pos = _read_head(path)
    check_size(path, n2, n1, 3)
    data = Path(path).read_bytes()
    image = np.empty((n1, n2, 3), np.float32)  # decoded in place: no RGBE copy of the whole image
    done = _kernel("decode", _decode_kernel)(np.frombuffer(data, np.uint8), pos, n1, n2,
                                             np.zeros((n2, 4), np.uint8), image)
    del data
    if done < n1:
        raise FormatError(f"{path}: the pixel data ends or breaks at scanline {done} of {n1}; the file is "
                          "truncated or damaged")
    attrs["orientation"] = f"{s1.decode()}{a1.decode()} {s2.decode()}{a2.decode()}"
    if a1 == b"X":  # scanlines are columns
        image = image.transpose(1, 0, 2)
        s1, s2 = s2, s1
    if s1 == b"+":  # +Y: the first scanline is the bottom row
        image = image[::-1]
    if s2 == b"-":  # -X: right to left
        image = image[:, ::-1]
    image = np.ascontiguousarray(image)  # a copy only for the rare orientations
    divide = np.float32(attrs["exposure"]) * np.asarray(attrs["colorcorr"], np.float32)
    if np.any(divide != 1):
        image /= divide
    meta = {"format": "hdr", "bit_depth": 32, "sample_type": "rgbe", "channels": ["R", "G", "B"],
            "display_encoded": False, "attributes": attrs}
    return image, meta


def _encode_kernel():
    import numba

    @numba.njit(cache=True, nogil=True)
    def encode(rgbe, out):
        """New-style RLE of every scanline (rows x width x 4 uint8) into ``out``; returns bytes used."""
        rows, width = rgbe.shape[0], rgbe.shape[1]
        pos = 0
        for y in range(rows):
            out[pos] = 2
            out[pos + 1] = 2
            out[pos + 2] = width >> 8
            out[pos + 3] = width & 255
            pos += 4
            for c in range(4):
                x = 0
                while x < width:
                    # the next run of 4 or more equal bytes from x (or none)
                    beg = x
                    run = 0
                    while beg < width:
                        run = 1
                        while run < 127 and beg + run < width and rgbe[y, beg + run, c] == rgbe[y, beg, c]:
                            run += 1
                        if run >= 4:
                            break
                        beg += run
                    if run < 4:
                        beg = width
                    while x < beg:  # literal bytes up to the run
                        count = min(128, beg - x)
                        out[pos] = count
                        pos += 1
                        for k in range(count):
                            out[pos + k] = rgbe[y, x + k, c]
                        pos += count
                        x += count
                    if beg < width:
                        out[pos] = 128 + run
                        out[pos + 1] = rgbe[y, beg, c]
                        pos += 2
                        x = beg + run
        return pos

    return encode


def _setcolr_kernel():
    import math

    import numba

    @numba.njit(cache=True, nogil=True)
    def setcolr(rgb, out):
        """Radiance's setcolr per pixel in one pass: E from frexp of the largest component, mantissas
        truncated; negative and NaN components 0, +inf the largest float32, grey (C = 1) as R = G = B."""
        h, w, c = rgb.shape
        for y in range(h):
            for x in range(w):
                r = rgb[y, x, 0]
                g = rgb[y, x, 1 % c]
                b = rgb[y, x, 2 % c]
                r = r if r > 0 else 0.0  # negative and NaN -> 0
                g = g if g > 0 else 0.0
                b = b if b > 0 else 0.0
                d = max(r, g, b)
                if d <= 1e-32:
                    out[y, x, 0] = out[y, x, 1] = out[y, x, 2] = out[y, x, 3] = 0
                    continue
                if d > 3.4028234663852886e38:  # +inf: the largest float32
                    d = 3.4028234663852886e38
                    r, g, b = min(r, d), min(g, d), min(b, d)
                m, e = math.frexp(d)
                f = m * 256.0 / d
                out[y, x, 0] = min(int(r * f), 255)
                out[y, x, 1] = min(int(g * f), 255)
                out[y, x, 2] = min(int(b * f), 255)
                out[y, x, 3] = min(max(e + 128, 0), 255)

    return setcolr


def encode_hdr(image: np.ndarray, rle: bool = True) -> bytes:
    """A float32 H x W x (1 or 3) image -> the bytes of a Radiance RGBE file."""
    from lenslab.io.encode import note_non_finite

    note_non_finite(image, "Radiance HDR", "0 (NaN, -inf) and the largest float (+inf)")
    h, w, c = image.shape
    rgbe = np.empty((h, w, 4), np.uint8)
    _kernel("setcolr", _setcolr_kernel)(np.ascontiguousarray(image, np.float32), rgbe)
    header = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\nSOFTWARE=lenslab\n\n-Y %d +X %d\n" % (h, w)
    if not rle or not 8 <= w <= 0x7FFF:
        return header + rgbe.tobytes()
    out = np.empty(h * (4 + 4 * (w + (w + 127) // 128)), np.uint8)  # worst case: all literal
    used = _kernel("encode", _encode_kernel)(np.ascontiguousarray(rgbe), out)
    return header + out[:used].tobytes()
