"""What tifffile logs about a damaged TIFF (an Exif IFD pointer beyond the file's end, TIFF 6.0 section 2: an offset
into the file) reaches a command as one note, not as tifffile's own line on standard error once per opening."""

from __future__ import annotations

import struct
import subprocess
import sys
from fractions import Fraction

import numpy as np

import lenslab.io as lio


def test_an_exif_pointer_beyond_the_end_is_one_note(tmp_path):
    path = tmp_path / "far.tif"
    lio.write(path, np.full((8, 12, 3), 0.5, np.float32), exif={"Make": "Acme", "FocalLength": Fraction(68, 10)})
    data = bytearray(path.read_bytes())
    at = data.find(struct.pack("<HHI", 0x8769, 4, 1))  # the first IFD's ExifIFD entry: LONG, count 1
    assert at > 0
    data[at + 8:at + 12] = struct.pack("<I", 0xFFFFFFF0)
    path.write_bytes(bytes(data))
    import tifffile

    with tifffile.TiffFile(path) as tif:  # the outside reading: tifffile reads the pixels all the same
        np.testing.assert_array_equal(tif.pages[0].asarray(), np.full((8, 12, 3), 0.5, np.float32))
    done = subprocess.run([sys.executable, "-m", "lenslab", "convert", str(path), "-o", str(tmp_path / "o.exr")],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    lines = [line for line in done.stderr.splitlines() if not line.startswith("converted ")]
    assert all(line.startswith("lenslab convert: note: ") for line in lines), lines
    assert len([line for line in lines if "4294967280" in line and "tifffile" in line]) == 1, lines
