"""A photo whose EXIF holds its focal length and focal plane as TIFF FLOAT or DOUBLE values (Pillow's ``Image.Exif``
writes a Python float so, type 12) keeps them through ``lenslab convert``, written as the RATIONALs Exif asks for:
``--from exif`` read them on the photo, and its copy was left without them ("of a type or value no camera writes").

The outside values: exiftool's reading of the photo's types and of the copy's values, and the field of view from the
photo's numbers transcribed in float64 (a 6 x 4 mm sensor behind 10 mm)."""

from __future__ import annotations

import math
import subprocess

import numpy as np
import pytest

from tests.exif.exif_tools import EXIFTOOL, exiftool, from_exif_fov, needs_exiftool, run

PIL = pytest.importorskip("PIL")
pytestmark = needs_exiftool


def pillow_photo(path, value_type: str):
    """A 60 x 40 JPEG of FocalLength 10 mm and 10 pixels a millimetre on the focal plane, held as ``value_type``:
    ``double`` (12) as Pillow's ``Image.Exif`` writes a Python float, ``float`` (11) in a block laid out here by hand
    (TIFF 6.0 section 2: an IFD of 12-byte entries, a 4-byte value in its entry)."""
    import struct

    from PIL import Image

    image = Image.fromarray(np.full((40, 60, 3), 128, np.uint8))
    if value_type == "double":
        exif = Image.Exif()
        exif[0x010F], exif[0x0110] = "Acme", "Pillow One"
        ifd = exif.get_ifd(0x8769)
        ifd.update({0x920A: 10.0, 0xA20E: 10.0, 0xA20F: 10.0})
        ifd[0xA210], ifd[0xA002], ifd[0xA003] = 4, 60, 40  # (unit 4: millimetres)
        image.save(path, exif=exif.tobytes(), quality=90)
        return path

    def ifd(entries, at):  # entries: (tag, type, count, 4 bytes); text values follow the IFD
        tail, out = b"", []
        data_at = at + 2 + 12 * len(entries) + 4
        for tag, kind, count, value in entries:
            if len(value) > 4:
                out.append(struct.pack("<HHII", tag, kind, count, data_at + len(tail)))
                tail += value + b"\0" * (len(value) % 2)  # (each value at an even offset)
            else:
                out.append(struct.pack("<HHI", tag, kind, count) + value.ljust(4, b"\0"))
        return struct.pack("<H", len(entries)) + b"".join(out) + b"\0" * 4 + tail

    first = [(0x010F, 2, 5, b"Acme\0"), (0x0110, 2, 11, b"Pillow One\0")]
    size = len(ifd(first + [(0x8769, 4, 1, b"")], 8))
    ten = struct.pack("<f", 10.0)
    exif_ifd = [(0x920A, 11, 1, ten), (0xA002, 4, 1, struct.pack("<I", 60)), (0xA003, 4, 1, struct.pack("<I", 40)),
                (0xA20E, 11, 1, ten), (0xA20F, 11, 1, ten), (0xA210, 3, 1, struct.pack("<H", 4))]
    block = (b"II*\0" + struct.pack("<I", 8) + ifd(first + [(0x8769, 4, 1, struct.pack("<I", 8 + size))], 8)
             + ifd(exif_ifd, 8 + size))
    image.save(path, exif=b"Exif\0\0" + block, quality=90)
    return path


def stored_types(path) -> dict:
    out = subprocess.run([EXIFTOOL, "-v3", str(path)], capture_output=True, text=True, check=True, timeout=60).stdout
    lines = out.splitlines()
    return {name: lines[k + 1].split("(")[1].split(")")[0].split(", ")[1].split("[")[0]
            for k, line in enumerate(lines) for name in ("FocalLength", "FocalPlaneXResolution")
            if line.strip().split(")  ")[-1].startswith(f"{name} =")}


@pytest.mark.parametrize("value_type", ["double", "float"])
@pytest.mark.parametrize("ext", ["jpg", "tif", "exr"])
def test_float_and_double_focal_values_are_carried(tmp_path, capsys, value_type, ext):
    source = pillow_photo(tmp_path / "p.jpg", value_type)
    assert stored_types(source) == {"FocalLength": value_type, "FocalPlaneXResolution": value_type}
    expected = math.degrees(2 * math.atan(6.0 / (2 * 10.0)))  # 60 pixels at 10 a millimetre, behind 10 mm
    assert from_exif_fov(capsys, source, tmp_path) == pytest.approx(expected, abs=1e-9)
    out = tmp_path / f"copy.{ext}"
    code, err = run(capsys, "convert", source, "-o", out)
    assert code == 0 and "not carried" not in err, err
    if ext != "exr":
        tags = exiftool(out, "FocalLength", "FocalPlaneXResolution", "Model")
        assert (tags["FocalLength"], tags["FocalPlaneXResolution"], tags["Model"]) == (10, 10, "Pillow One")
        assert stored_types(out) == {"FocalLength": "rational64u", "FocalPlaneXResolution": "rational64u"}
    assert from_exif_fov(capsys, out, tmp_path) == pytest.approx(expected, abs=1e-9)
