"""Where a file keeps its Exif block: a JPEG's ``APP1 Exif`` segment, a PNG's ``eXIf`` chunk, a TIFF's own IFDs, a
HEIF's Exif item (through libheif), an EXR's header attributes (OpenImageIO's names). Only headers are read: a
JPEG's segments before its scan, a PNG's chunk headers (a seek past each chunk's data), a TIFF's IFDs."""

from __future__ import annotations

import os
import struct

from lenslab.io.exif.ifd import Damaged, parse
from lenslab.io.tiff.walk import file_read

#: the largest Exif block read, bytes (a camera file's limit; a JPEG's APP1 holds at most 64 KiB)
MAX_BYTES = 4 << 20
#: bytes of a JPEG searched for its APP1 segment (segments before the scan; each at most 64 KiB)
JPEG_HEAD = 1 << 20
#: PNG chunks walked before giving up on an eXIf chunk
PNG_CHUNKS = 1 << 16


class TooLarge(ValueError):
    """An Exif block larger than :data:`MAX_BYTES`."""


def _of_bytes(block: bytes) -> tuple[dict, list[str]]:
    if block.startswith(b"Exif\0\0"):  # (JPEG's APP1 signature, which some writers put in a PNG's eXIf chunk)
        block = block[6:]
    if len(block) > MAX_BYTES:
        raise TooLarge(f"its Exif block holds {len(block)} bytes, more than the {MAX_BYTES >> 20} MiB read")
    return parse(lambda at, n: block[at:at + n], len(block))


def _jpeg(path) -> bytes | None:
    from lenslab.io.exif_orientation import jpeg_exif

    with open(path, "rb") as f:
        return jpeg_exif(f.read(JPEG_HEAD))


def _png(path) -> bytes | None:
    size = os.path.getsize(path)
    with open(path, "rb") as f:
        pos = 8
        for _ in range(PNG_CHUNKS):
            f.seek(pos)
            head = f.read(8)
            if len(head) < 8:
                return None
            length, kind = struct.unpack(">I4s", head)
            if kind == b"IEND":
                return None
            if kind == b"eXIf":
                if length > MAX_BYTES:
                    raise TooLarge(f"its eXIf chunk holds {length} bytes, more than the {MAX_BYTES >> 20} MiB read")
                if pos + 12 + length > size:
                    raise Damaged(f"its eXIf chunk declares {length} bytes; the file holds {size - pos - 12}")
                return f.read(length)
            pos += 12 + length
    return None


def _tiff(path) -> tuple[dict, list[str]] | None:
    size = os.path.getsize(path)
    with open(path, "rb") as f:
        return parse(file_read(f), size)


def _heif(path) -> bytes | None:
    try:
        import pillow_heif
    except ImportError:  # (reading the image says how to install it)
        return None
    return pillow_heif.open_heif(str(path)).info.get("exif") or None


def _exr(path) -> tuple[dict, list[str]]:
    import OpenEXR

    from lenslab.exif_tags import exr_tags
    from lenslab.io.exr.chunks import parse_header
    from lenslab.library_output import quiet_library

    parse_header(path)  # (its budget: a header the bindings would build in memory many times its bytes)
    with quiet_library():
        header = OpenEXR.File(str(path), header_only=True).parts[0].header
    return exr_tags(header), []


def read_tags(path, fmt: str) -> tuple[dict, list[str]] | None:
    """(the carried tags of the file at ``path`` of format ``fmt``, the names of those it holds in a form no camera
    writes), or None where the format keeps no Exif or the file holds none; :class:`Damaged` or :class:`TooLarge`
    for a block that cannot be read."""
    if fmt == "exr":
        return _exr(path)
    if fmt == "tiff":
        return _tiff(path)
    find = {"jpg": _jpeg, "png": _png, "heif": _heif}.get(fmt)
    block = find(path) if find is not None else None
    return _of_bytes(block) if block is not None else None
