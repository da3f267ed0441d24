"""A PNG whose eXIf chunk starts with JPEG's ``Exif\\0\\0`` (as some writers put it; exiftool reads it, warning of an
"Improper Exif00 header") gives its camera to its copies, as a HEIC's Exif item so prefixed does: it was left out
with a note ("no TIFF header").

The outside values: exiftool's readings of the photo (its warning and tags) and of the copy; the chunk is laid out
here by the PNG specification (length, type, data, CRC-32 of type and data)."""

from __future__ import annotations

import struct
import zlib

import numpy as np
import pytest

from tests.exif.exif_tools import exiftool, needs_exiftool, photo, run

pytestmark = needs_exiftool


def prefixed_png(tmp_path):
    """A PNG (OpenCV's) with an eXIf chunk after IHDR holding ``Exif\\0\\0`` and the TIFF block exiftool wrote into a
    JPEG (its APP1 payload)."""
    import cv2

    jpg = photo(tmp_path / "p.jpg", 60, 40, "-Make=Acme", "-Model=Prefixed", "-FocalLength=6.81",
                "-FocalLengthIn35mmFormat=26")
    data = jpg.read_bytes()
    at = data.index(b"Exif\0\0")
    length = struct.unpack(">H", data[at - 2:at])[0]
    block = data[at:at - 2 + length]  # "Exif\0\0" and the TIFF structure
    ok, png = cv2.imencode(".png", np.full((40, 60, 3), 128, np.uint8))
    png = png.tobytes()
    chunk = struct.pack(">I", len(block)) + b"eXIf" + block + struct.pack(">I", zlib.crc32(b"eXIf" + block))
    out = tmp_path / "prefixed.png"
    out.write_bytes(png[:33] + chunk + png[33:])  # (the signature, 8 bytes, and IHDR, 25)
    return out


def test_a_prefixed_exif_chunk_goes_with_the_copy(tmp_path, capsys):
    source = prefixed_png(tmp_path)
    read = exiftool(source, "Make", "Model", "FocalLength", "Warning")
    assert (read["Make"], read["Model"], read["FocalLength"]) == ("Acme", "Prefixed", 6.81)
    assert "Exif00" in read["Warning"]
    out = tmp_path / "copy.jpg"
    code, err = run(capsys, "convert", source, "-o", out)
    assert code == 0 and "not carried" not in err, err
    tags = exiftool(out, "Make", "Model", "FocalLength", "FocalLengthIn35mmFormat")
    assert (tags["Make"], tags["Model"], tags["FocalLength"], tags["FocalLengthIn35mmFormat"]) == (
        "Acme", "Prefixed", 6.81, 26)
