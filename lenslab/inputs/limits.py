"""Size limits checked before any pixel memory is allocated (decompression-bomb guard).

Raw formats (PPM/PGM/PBM, PFM) are also checked against the bytes actually in the file; compressed
ones (EXR, PNG, JPG) can legitimately be tiny on disk, so for them this pixel cap is the guard. The
default, 2**29 pixels (a 32768 x 16384 panorama, 6 GiB as float32 RGB), can be changed with the
environment variable ``LENSLAB_MAX_PIXELS``.
"""

from __future__ import annotations

import os

from lenslab.errors import FormatError


def env_int(name: str, default: int) -> int:
    try:
        return max(1, int(os.environ.get(name, default)))
    except ValueError:
        return default


#: largest image accepted, in pixels
MAX_PIXELS = env_int("LENSLAB_MAX_PIXELS", 1 << 29)
#: largest width or height accepted
MAX_SIDE = 1 << 20


def check_size(path, width: int, height: int, channels: int = 1) -> None:
    """Refuse non-positive or absurd dimensions with a FormatError naming the file."""
    if width <= 0 or height <= 0:
        raise FormatError(f"{path}: the header gives a size of {width} x {height}; the file is damaged")
    if width > MAX_SIDE or height > MAX_SIDE or width * height > MAX_PIXELS:
        raise FormatError(
            f"{path}: the header claims {width} x {height} pixels, beyond the limit of {MAX_PIXELS} pixels "
            f"({MAX_SIDE} per side); the file is damaged or hostile (raise LENSLAB_MAX_PIXELS to read a "
            "genuine image this large)")
