"""A damaged or huge EXIF block never fails a convert: it is left out with one note and the image is written. The
blocks here are laid out by hand from TIFF 6.0's structure (a header, IFDs of 12-byte entries), not by lenslab."""

from __future__ import annotations

import struct

import cv2
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from tests.exif.exif_tools import exiftool, needs_exiftool, run


def jpeg_with_app1(path, block: bytes):
    """A 48 x 32 JPEG (OpenCV's) with ``Exif\\0\\0`` + ``block`` as its APP1 segment, right after its start."""
    data = cv2.imencode(".jpg", np.full((32, 48, 3), 100, np.uint8))[1].tobytes()
    payload = b"Exif\0\0" + block
    path.write_bytes(data[:2] + b"\xff\xe1" + struct.pack(">H", len(payload) + 2) + payload + data[2:])
    return path


def entry(tag: int, kind: int, count: int, field: bytes) -> bytes:
    return struct.pack("<HHI", tag, kind, count) + field.ljust(4, b"\0")


def ifd(*entries: bytes) -> bytes:
    return struct.pack("<H", len(entries)) + b"".join(entries) + b"\0\0\0\0"


def header(first: int = 8) -> bytes:
    return b"II*\0" + struct.pack("<I", first)


def exif_notes(err: str) -> list[str]:
    return [line for line in err.splitlines() if "note:" in line and "EXIF" in line]


def convert_said(capsys, source, out) -> list[str]:
    code, err = run(capsys, "convert", source, "-o", out)
    assert code == 0, err
    import tifffile

    written = tifffile.imread(out) if out.suffix == ".tif" else cv2.imread(str(out))
    assert written.shape[:2] == (32, 48)
    return exif_notes(err)


@needs_exiftool
@pytest.mark.parametrize("block", [
    pytest.param(header(9999), id="first IFD outside the block"),
    pytest.param(header() + struct.pack("<H", 5000) + b"\0" * 24, id="entries past the end"),
    pytest.param(header() + ifd(entry(0x010F, 2, 40, struct.pack("<I", 60000))), id="a value outside the block"),
    pytest.param(b"XX*\0\0\0\0\0", id="no TIFF header"),
    pytest.param(b"II*", id="cut short"),
])
def test_a_damaged_block_is_left_out_with_one_note(tmp_path, capsys, block):
    source = jpeg_with_app1(tmp_path / "damaged.jpg", block)
    notes = convert_said(capsys, source, tmp_path / "out.png")
    assert len(notes) == 1 and "not carried" in notes[0], notes
    assert "Make" not in exiftool(tmp_path / "out.png", "Make")


@needs_exiftool
def test_a_huge_png_exif_chunk_is_left_out_with_one_note(tmp_path, capsys):
    """A PNG whose eXIf chunk holds 5 MiB (past the 4 MiB a camera file may hold)."""
    import zlib

    png = cv2.imencode(".png", np.full((32, 48, 3), 100, np.uint8))[1].tobytes()
    data = header() + ifd(entry(0x010F, 2, 4, b"Big\0")) + b"\0" * (5 << 20)
    chunk = struct.pack(">I", len(data)) + b"eXIf" + data + struct.pack(">I", zlib.crc32(b"eXIf" + data))
    (tmp_path / "huge.png").write_bytes(png[:33] + chunk + png[33:])
    assert exiftool(tmp_path / "huge.png", "Make")["Make"] == "Big"  # (a PNG exiftool reads)
    notes = convert_said(capsys, tmp_path / "huge.png", tmp_path / "out.jpg")
    assert len(notes) == 1 and "4 MiB" in notes[0], notes
    assert "Make" not in exiftool(tmp_path / "out.jpg", "Make")


@needs_exiftool
def test_tags_no_camera_writes_are_named_and_the_rest_carried(tmp_path, capsys):
    """Make stored as a LONG (a number, not text): named in the one note; Model (ASCII) carried."""
    model = b"Fine Model\0"
    first = ifd(entry(0x010F, 4, 1, struct.pack("<I", 7)), entry(0x0110, 2, len(model), struct.pack("<I", 8 + 30)))
    source = jpeg_with_app1(tmp_path / "odd.jpg", header() + first + model)
    notes = convert_said(capsys, source, tmp_path / "out.tif")
    assert len(notes) == 1 and "Make" in notes[0], notes
    assert exiftool(tmp_path / "out.tif", "Model")["Model"] == "Fine Model"


@needs_exiftool
def test_an_exif_pointer_back_to_the_first_ifd_ends(tmp_path, capsys):
    """The first IFD's Exif pointer names the first IFD itself: read once, no loop."""
    make = b"Loop\0"
    first = ifd(entry(0x010F, 2, len(make), make[:4] if len(make) <= 4 else struct.pack("<I", 8 + 30)),
                entry(0x8769, 4, 1, struct.pack("<I", 8)))
    source = jpeg_with_app1(tmp_path / "loop.jpg", header() + first + make)
    assert convert_said(capsys, source, tmp_path / "out.png") == []
    assert exiftool(tmp_path / "out.png", "Make")["Make"] == "Loop"


@settings(max_examples=300)
@given(st.binary(max_size=400), st.sampled_from([b"II*\0", b"MM\0*"]))
def test_any_bytes_read_as_tags_or_as_damage(body, magic):
    """Whatever follows a TIFF header, the reader gives carried tags of their kinds, or Damaged: no other error,
    no read past the block."""
    from fractions import Fraction

    from lenslab.exif_tags import TAGS
    from lenslab.io.exif.ifd import Damaged, parse

    block = magic + body
    reads = []

    def read(at, n):
        reads.append((at, n))
        return block[at:at + n]

    try:
        tags, odd = parse(read, len(block))
    except Damaged:
        return
    finally:
        assert all(at >= 0 and at + n <= len(block) for at, n in reads), reads
    kinds = {"text": str, "int": int, "ratio": Fraction}
    assert all(isinstance(v, kinds[TAGS[k].kind]) for k, v in tags.items())
    assert set(odd) <= set(TAGS)
