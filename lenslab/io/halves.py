"""float32 -> float16 for every writer of half floats (EXR, TIFF): one stage, so a file holds the same halves
whatever its format.

Finite values beyond half's range are clamped to +-65504 (the largest finite half) and counted in one
:class:`HalfOverflowWarning` a write, worded for the format; infinities stay infinite and NaN stays NaN (its payload
as NumPy's cast keeps it); every other value is NumPy's IEEE 754 cast (round to nearest even, subnormal halves). One
compiled pass over a C-contiguous float32 image (``lenslab.cxx_kernels.to_half``, ``src/native/halves.cpp``), else
:func:`to_half_reference`'s NumPy blocks; with ``in_place`` the halves are made in the image's own memory.

>>> import warnings
>>> with warnings.catch_warnings(record=True) as said:
...     warnings.simplefilter("always")
...     out = to_half(np.array([[[1.0, 70000.0, -1e30]], [[np.inf, np.nan, 1.0 / 3.0]]], np.float32), fmt="TIFF",
...                   option="sample_type")
>>> out.tolist()
[[[1.0, 65504.0, -65504.0]], [[inf, nan, 0.333251953125]]]
>>> str(said[0].message)
"2 value(s) beyond half's range were clamped to +-65504 in the half TIFF; write with sample_type='float' to keep them"
"""

from __future__ import annotations

import warnings

import numpy as np

from lenslab.errors import FormatError

#: the largest finite IEEE 754 binary16 value
HALF_MAX = 65504.0


class HalfOverflowWarning(UserWarning):
    """Values beyond the range of half floats were clamped to +-65504 when writing a half-float file (EXR, TIFF).

    ``command_line`` is the same note in the words of lenslab's commands, which show that one."""

    def __init__(self, message: str, command_line: str | None = None):
        super().__init__(message)
        self.command_line = command_line or message


def to_half(image: np.ndarray, rows: int | None = None, in_place: bool = False, fmt: str = "EXR",
            option: str = "pixel_type") -> np.ndarray:
    """float32 -> float16 with finite values beyond half's range clamped (one :class:`HalfOverflowWarning` with
    their count, naming ``fmt`` and the writer's ``option`` that keeps them); one compiled pass over a C-contiguous
    float32 image, else :func:`to_half_reference`'s blocks of ``rows`` rows (None: about 2 MB of float32): the only
    full-size allocation is the result. ``in_place``: the result is made in the first half of ``image``'s own
    memory (no allocation of the image's size; ``image`` is overwritten) when ``image`` is a C-contiguous, writable
    float32 array."""
    from lenslab.native import extension

    contiguous = image.dtype == np.float32 and image.flags.c_contiguous and image.size > 0
    own = in_place and contiguous and image.flags.writeable
    if own:  # element i of the result lies at byte 2i, before element i of the source (byte 4i)
        out = image.reshape(-1).view(np.float16)[:image.size].reshape(image.shape)
    else:
        out = np.empty(image.shape, np.float16)
    if contiguous:  # (in order on one thread: a half written never reaches a float not yet read)
        n = extension(FormatError).to_half(image.reshape(-1), out.reshape(-1).view(np.uint16))
    else:
        n = to_half_reference(image, out, rows)
    if n:
        clamped = f"{n} value(s) beyond half's range were clamped to +-{HALF_MAX:g} in the half {fmt}"
        warnings.warn(HalfOverflowWarning(f"{clamped}; write with {option}='float' to keep them",
                                          f"{clamped}; write with --pixel-type float to keep them"), stacklevel=4)
    return out


def to_half_reference(image: np.ndarray, out: np.ndarray, rows: int | None = None) -> int:
    """NumPy's :func:`to_half` of ``image`` into ``out`` (float16, its shape; it may be the first half of a
    C-contiguous ``image``'s memory: blocks taken from the start never overwrite a value not yet read, as
    NumPy buffers each block's overlap), ``rows`` rows at a time; the count of values clamped."""
    n = 0
    rows = rows or max(1, (2 << 20) // max(1, image[:1].nbytes))
    for y in range(0, image.shape[0], rows):
        block = image[y:y + rows]
        big = np.abs(block) > HALF_MAX  # NaN compares False; infinities are kept as they are, below
        if big.any():
            big &= np.isfinite(block)
            count = int(np.count_nonzero(big))
            if count:
                n += count
                block = np.where(big, np.copysign(np.float32(HALF_MAX), block), block)
        out[y:y + rows] = block.astype(np.float16) if np.shares_memory(out, image) else block
    return n
