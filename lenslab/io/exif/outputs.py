"""Carried tags put where each format keeps them: a JPEG's ``APP1 Exif`` segment (after JFIF's ``APP0``, before
everything else: CIPA DC-008 section 4.5.4), a PNG's ``eXIf`` chunk (PNG 3rd edition, before the image data), a
TIFF's first IFD (Make, Model, Orientation: TIFF's own tags) and an Exif IFD it points to, an EXR's header
(:func:`lenslab.exif_tags.exr_attributes`)."""

from __future__ import annotations

import os
import struct

from lenslab.io.exif.ifd import build, encode, exif_ifd, ifd_bytes
from lenslab.exif_tags import EXIF_POINTER, TAGS
from lenslab.io.tiff.walk import entries, file_read, header


#: the first-IFD tags Exif 2.32 requires of a JPEG: 72 pixels per inch (the conventional value, where nothing says
#: how large to print), YCbCr samples centred (as JFIF's and libjpeg's are)
JPEG_FIRST = ((0x011A, 5, 1, struct.pack("<II", 72, 1)), (0x011B, 5, 1, struct.pack("<II", 72, 1)),
              (0x0128, 3, 1, struct.pack("<H", 2)), (0x0213, 3, 1, struct.pack("<H", 1)))


def colour_entries(srgb: bool, jpeg: bool = False) -> tuple:
    """The Exif IFD's FlashpixVersion (0100), ColorSpace (1: sRGB codes; 0xFFFF uncalibrated: another profile's, or
    linear floats) and, for a JPEG, ComponentsConfiguration (Y, Cb, Cr): tags Exif 2.32 requires."""
    out = ((0xA000, 7, 4, b"0100"), (0xA001, 3, 1, struct.pack("<H", 1 if srgb else 0xFFFF)))
    return out + (((0x9101, 7, 4, b"\1\2\3\0"),) if jpeg else ())


def jpeg_with_exif(jpg: bytes, tags: dict, srgb: bool = True) -> bytes:
    """``jpg`` with an ``APP1 Exif`` segment of ``tags`` after its start and its ``APP0`` (JFIF); ``srgb``: its
    codes are sRGB's (no other ICC profile)."""
    block = b"Exif\0\0" + build(tags, JPEG_FIRST, colour_entries(srgb, jpeg=True))
    if len(block) + 2 > 0xFFFF:
        raise ValueError(f"an Exif block of {len(block)} bytes does not fit in a JPEG segment")
    at = 4 + int.from_bytes(jpg[4:6], "big") if jpg[2:4] == b"\xff\xe0" else 2  # JFIF's APP0 stays first
    return bytes(jpg[:at]) + b"\xff\xe1" + struct.pack(">H", len(block) + 2) + block + bytes(jpg[at:])


def png_with_exif(png: bytes, tags: dict) -> bytes:
    """``png`` with an ``eXIf`` chunk of ``tags`` right after its ``IHDR``."""
    from lenslab.io.colour.png_cicp import after_ihdr

    return after_ihdr(png, b"eXIf", build(tags))


def append_exif_ifd(path, tags: dict, srgb: bool = True) -> None:
    """Give the little-endian TIFF at ``path`` (one image, as tifffile writes it: classic, or BigTIFF for more than
    4 GB) the first-IFD tags of ``tags`` (Make, Model, Orientation) and an Exif IFD: both written at the end of the
    file, a copy of its first IFD with them then named first in its header (tifffile writes neither the Exif IFD nor
    its pointer; an IFD may lie anywhere in the file, and its values keep their offsets). A BigTIFF's IFDs are
    BigTIFF's, its pointer an IFD8 (as libtiff writes it). PixelXDimension and PixelYDimension are left out: Exif
    gives them to compressed images only (a TIFF's frame is its own ImageWidth and ImageLength). ``srgb``: its
    samples are sRGB codes."""
    tags = {n: v for n, v in tags.items() if n not in ("PixelXDimension", "PixelYDimension")}
    with open(path, "r+b") as f:
        found = header(f.read(16))
        if found is None or found.order != "<" or not found.standard:
            raise ValueError("an Exif IFD is written into little-endian TIFF only")
        big = found.big
        offset, pointer_type = ("<Q", 18) if big else ("<I", 4)
        ours = {TAGS[n].tag: n for n, v in tags.items() if TAGS[n].ifd == "0"}
        walked = entries(file_read(f), os.fstat(f.fileno()).st_size, found.first, "<", big)
        kept = [e for e in walked[0] if e[0] not in ours and e[0] != EXIF_POINTER]
        carried = kept + [(TAGS[n].tag, *encode(n, tags[n])) for n in ours.values()]
        f.seek(0, 2)
        end = f.tell()
        at = end + end % 2
        size = len(ifd_bytes(carried + [(EXIF_POINTER, pointer_type, 1, b"")], at, big))
        exif_at = at + size + size % 2
        block = ifd_bytes(carried + [(EXIF_POINTER, pointer_type, 1, struct.pack(offset, exif_at))], at, big)
        f.write(b"\0" * (end % 2) + block + b"\0" * (size % 2) + exif_ifd(tags, exif_at, colour_entries(srgb), big))
        f.seek(8 if big else 4)
        f.write(struct.pack(offset, at))
