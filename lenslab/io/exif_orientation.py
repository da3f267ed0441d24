"""A JPEG's EXIF orientation: the ``Orientation`` tag (0x0112) of the first IFD of its ``APP1`` Exif segment, and the
turn that shows the image as the camera meant it (a phone held upright stores its photo on its side with
``Orientation`` 6). OpenCV's ``imread``, Pillow's ``ImageOps.exif_transpose``, every viewer, and libheif for a HEIC's
``irot``/``imir``, show the image so turned; lenslab reads a JPEG so too.

Only the segments before the image data are looked at; a missing, damaged or out-of-range tag is 1 (as stored).
"""

from __future__ import annotations

import numpy as np

#: what each value other than 1 does to the stored image to show it (EXIF 2.3, "Orientation")
TURNS = {2: "mirrored left to right", 3: "turned 180 degrees", 4: "mirrored top to bottom",
         5: "mirrored across its main diagonal", 6: "turned 90 degrees clockwise",
         7: "mirrored across its other diagonal", 8: "turned 90 degrees anticlockwise"}


def jpeg_orientation(data: bytes) -> int:
    """The EXIF ``Orientation`` (1 to 8) of the JPEG ``data``; 1 where none is recorded or it cannot be read."""
    block = jpeg_exif(data)
    return 1 if block is None else _tiff_orientation(block)


def jpeg_exif(data: bytes) -> bytes | None:
    """The TIFF structure of the JPEG ``data``'s first ``APP1 Exif`` segment (before its scan; cut short where the
    segment runs past ``data``), or None where it holds none."""
    pos, n = 2, len(data)
    while pos + 4 <= n and data[pos] == 0xFF:
        marker = data[pos + 1]
        if marker == 0xFF:
            pos += 1
            continue
        if marker in (0xD9, 0xDA):  # end of image, start of scan: no header segment follows
            break
        if marker == 0x01 or 0xD0 <= marker <= 0xD7:
            pos += 2
            continue
        length = int.from_bytes(data[pos + 2:pos + 4], "big")
        if length < 2:
            break
        if marker == 0xE1 and data[pos + 4:pos + 10] == b"Exif\x00\x00":
            return data[pos + 10:pos + 2 + length]
        pos += 2 + length
    return None


def _tiff_orientation(tiff: bytes) -> int:
    """The ``Orientation`` SHORT of the first IFD of an Exif segment's TIFF structure (of its entries the segment
    holds), or 1."""
    from lenslab.io.tiff.walk import Outside, entries, header

    found = header(tiff[:8])
    if found is None or found.version != 42:
        return 1
    try:
        walked = entries(lambda at, n: tiff[at:at + n], len(tiff), found.first, found.order, held=True)[0]
    except Outside:
        return 1
    value = next((int.from_bytes(f[:2], {"<": "little", ">": "big"}[found.order]) for tag, kind, _, f in walked
                  if tag == 0x0112 and kind == 3), 1)
    return value if 1 <= value <= 8 else 1


def turn(image: np.ndarray, orientation: int) -> np.ndarray:
    """The stored ``(H, W, C)`` image as shown for an EXIF ``orientation`` (a view of it, not a copy)."""
    if orientation in (5, 6, 7, 8):
        image = image.transpose(1, 0, 2)
    rows, cols = {2: (1, -1), 3: (-1, -1), 4: (-1, 1), 6: (1, -1), 7: (-1, -1), 8: (-1, 1)}.get(orientation, (1, 1))
    return image[::rows, ::cols]


def _header(path):
    """``(declared (W, H) or None, whether its EXIF orientation swaps its sides)`` from a photo's header, None where
    it cannot be read: the format's declared frame (as stored) and a JPEG's orientation (5 to 8, those lenslab
    applies)."""
    from lenslab.errors import LenslabError
    from lenslab.io.registry import get, sniff

    try:
        fmt = get(sniff(path))
        declared = fmt.declare(path) if fmt.declare is not None else None
        frame = (declared.width, declared.height) if declared is not None and declared.width > 0 < declared.height \
            else None
        with open(path, "rb") as f:
            head = f.read(2)
            if head == b"\xff\xd8":  # (only a JPEG's orientation is read: its segments before the scan)
                head += f.read((1 << 20) - 2)
    except (LenslabError, OSError, ValueError, EOFError, IndexError, OverflowError, ImportError):  # damaged, unread
        return None
    return frame, head[:2] == b"\xff\xd8" and jpeg_orientation(head) >= 5


def stored_size(path, size: tuple[int, int]) -> tuple[int, int]:
    """A photo's own stored frame (W, H, before its EXIF orientation: what EXIF's FocalPlaneXResolution counts
    across) from its header, whatever size its lens is asked at; where its format declares none, ``size`` (the
    photo as shown) turned back where a JPEG's EXIF orientation (5 to 8, those lenslab applies) swaps its sides."""
    header = _header(path)
    if header is None:
        return size
    frame, swaps = header
    return frame if frame is not None else (size[1], size[0]) if swaps else size


def shown_size(path) -> tuple[int, int] | None:
    """A photo's size as shown (W, H, after its EXIF orientation, as :func:`lenslab.io.read` gives it) from its
    header alone, None where its format declares no frame."""
    header = _header(path)
    if header is None or header[0] is None:
        return None
    (w, h), swaps = header
    return (h, w) if swaps else (w, h)
