"""Size limits checked before any pixel memory is allocated (decompression-bomb guard)."""

from __future__ import annotations

from lenslab.errors import FormatError

#: largest image accepted, in pixels (1 Gpx: 12 GB as float32 RGB)
MAX_PIXELS = 1 << 30
#: largest width or height accepted
MAX_SIDE = 1 << 20


def check_size(path, width: int, height: int, channels: int = 1) -> None:
    """Refuse non-positive or absurd dimensions with a FormatError naming the file."""
    if width <= 0 or height <= 0:
        raise FormatError(f"{path}: the header gives a size of {width} x {height}; the file is damaged")
    if width > MAX_SIDE or height > MAX_SIDE or width * height > MAX_PIXELS:
        raise FormatError(
            f"{path}: the header claims {width} x {height} pixels, beyond the limit of {MAX_PIXELS} pixels "
            f"({MAX_SIDE} per side); the file is damaged or hostile")
