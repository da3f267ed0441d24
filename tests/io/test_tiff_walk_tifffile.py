"""The TIFF walker that the TIFF reader's pre-check and the Exif parser share (:mod:`lenslab.io.tiff.walk`) reads the
first IFD of any small TIFF tifffile writes (classic and BigTIFF, both byte orders, extra tags of every numeric and
text type, held in the value field or at an offset) as tifffile reads it.

Outside value: ``tifffile.TiffFile(...).pages[0].tags``: each tag's code, type, count and value. Values compare
exactly: both read the same stored bytes (floats as stored, float32 for FLOAT).
"""

from __future__ import annotations

import io
import string
import struct

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

tifffile = pytest.importorskip("tifffile")

from lenslab.io.tiff.walk import CODES, SIZES as CODES_SIZE, chain, header, value_bytes  # noqa: E402

_INT = {1: (0, 255), 3: (0, 0xFFFF), 4: (0, 0xFFFFFFFF), 5: (0, 0xFFFFFFFF), 6: (-128, 127), 8: (-32768, 32767),
        9: (-(1 << 31), (1 << 31) - 1), 10: (-(1 << 31), (1 << 31) - 1), 16: (0, (1 << 64) - 1)}


@st.composite
def extra_tag(draw, code: int, big: bool):
    """One extratag of tifffile's ``imwrite``: (code, type, count, value, writeonce)."""
    kind = draw(st.sampled_from([1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12] + ([16] if big else [])))
    count = draw(st.integers(1, 6))
    if kind == 2:
        return code, 2, None, draw(st.text(string.ascii_letters + string.digits, min_size=1, max_size=12)), False
    if kind == 7:
        return code, 7, count, draw(st.binary(min_size=count, max_size=count)), False
    if kind in (11, 12):
        values = st.floats(width=32 if kind == 11 else 64, allow_nan=False, allow_infinity=False)
    else:
        values = st.integers(*_INT[kind])
    n = count * (2 if kind in (5, 10) else 1)
    return code, kind, count, tuple(draw(st.lists(values, min_size=n, max_size=n))), False


@st.composite
def small_tiff(draw) -> bytes:
    big = draw(st.booleans())
    codes = draw(st.lists(st.integers(65000, 65100), min_size=1, max_size=6, unique=True))
    shape = (draw(st.integers(1, 5)), draw(st.integers(1, 5)))
    dtype = draw(st.sampled_from([np.uint8, np.uint16, np.float32]))
    out = io.BytesIO()
    tifffile.imwrite(out, np.zeros(shape, dtype), bigtiff=big, byteorder=draw(st.sampled_from("<>")),
                     extratags=[draw(extra_tag(code, big)) for code in codes])
    return out.getvalue()


def _shown(kind: int, raw: bytes, order: str):
    """A value's stored bytes as text up to its first NUL, else as a tuple of numbers."""
    if kind == 2:
        return raw.split(b"\0", 1)[0].decode("ascii")
    return tuple(raw) if kind in (1, 7) else struct.unpack(order + CODES[kind] * (len(raw) // CODES_SIZE[kind]), raw)


def _theirs(value):
    """tifffile's value so too (its BYTE and UNDEFINED values are bytes, a single number a scalar)."""
    if isinstance(value, str):
        return value
    return tuple(value) if isinstance(value, (tuple, bytes)) else (value,)


@settings(max_examples=80, deadline=None)
@given(small_tiff())
def test_the_walker_reads_a_first_ifd_as_tifffile_does(data):
    read = lambda at, n: data[at:at + n]  # noqa: E731
    found = header(data[:16])
    assert found.standard
    first = next(chain(read, len(data), found, 1))
    ours = {tag: (kind, count, _shown(kind, value_bytes(read, len(data), found.order, kind, count, field), found.order))
            for tag, kind, count, field in first}
    with tifffile.TiffFile(io.BytesIO(data)) as tiff:
        assert found.order == tiff.byteorder and found.big == tiff.is_bigtiff
        tags = tiff.pages[0].tags
        theirs = {t.code: (int(t.dtype), t.count, _theirs(t.value)) for t in tags.values()}
    assert ours == theirs
