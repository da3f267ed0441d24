"""A PNG of 1000 eXIf chunks (the PNG specification, 3rd edition, section 11.3.6: "The eXIf chunk ... shall not
appear more than once") reads with one note, not libpng's "eXIf: duplicate" once per chunk on standard error; the
first chunk's EXIF (what libpng keeps too) is the one carried."""

from __future__ import annotations

import struct
import subprocess
import sys
import zlib

import cv2
import numpy as np

from lenslab.io.exif.ifd import build


def png_with_exif_chunks(path, blocks):
    data = cv2.imencode(".png", np.full((16, 24, 3), 90, np.uint8))[1].tobytes()
    chunks = b"".join(struct.pack(">I", len(b)) + b"eXIf" + b + struct.pack(">I", zlib.crc32(b"eXIf" + b))
                      for b in blocks)
    path.write_bytes(data[:33] + chunks + data[33:])  # after IHDR (8 + 25 bytes), before IDAT
    return path


def test_a_thousand_exif_chunks_give_one_note(tmp_path):
    first = build({"Make": "Acme", "FocalLengthIn35mmFilm": 26})
    src = png_with_exif_chunks(tmp_path / "many.png", [first] + [build({"Make": "Other"})] * 999)
    out = tmp_path / "out.png"
    done = subprocess.run([sys.executable, "-m", "lenslab", "convert", str(src), "-o", str(out)],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    lines = done.stderr.splitlines()
    assert not [line for line in lines if line.startswith("libpng")], lines[:3]
    notes = [line for line in lines if "note:" in line]
    assert len(notes) == 1 and "duplicate" in notes[0], lines[:5]
    assert notes[0].count("many.png") == 1, notes[0]  # (the command names the file; the note does not again)
    import exifread

    with open(out, "rb") as f:
        assert str(exifread.process_file(f, details=False)["Image Make"]) == "Acme"
