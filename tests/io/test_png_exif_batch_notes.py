"""A PNG with an eXIf chunk decoded while a batch's other thread decodes a damaged PNG keeps to its own notes: the
other file's libpng error is not read as its note, nor taken off standard error.

Outside values: libpng itself (through OpenCV) decoding the damaged PNG alone prints its error line (``libpng error:
IDAT: ...``) and decoding the PNG with one valid eXIf chunk alone prints nothing; exifread reads that chunk's Make.
The two decodes are made to overlap by waiting on events (no timing): the eXIf PNG's decode starts, the damaged one is
decoded whole, then the eXIf PNG's decode goes on. Before, the eXIf PNG's decode captured the process's standard
error and gave the note "libpng: IDAT: incorrect data check" to the valid file, and that line vanished."""

from __future__ import annotations

import struct
import subprocess
import sys
import threading
import warnings
import zlib

import cv2
import numpy as np

from lenslab.io import ldr
from lenslab.io.exif.ifd import build


def _chunk(kind: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))


def _pngs(tmp_path):
    img = (np.random.default_rng(1).random((32, 48, 3)) * 255).astype(np.uint8)
    png = cv2.imencode(".png", img)[1].tobytes()
    with_exif = tmp_path / "exif.png"
    with_exif.write_bytes(png[:33] + _chunk(b"eXIf", build({"Make": "Acme"})) + png[33:])
    damaged = bytearray(png)
    at = png.index(b"IDAT") + 14
    damaged[at:at + 20] = b"\xff" * 20
    bad = tmp_path / "bad.png"
    bad.write_bytes(bytes(damaged))
    return with_exif, bad


def _alone(path) -> str:
    code = f"import cv2; cv2.imread({str(path)!r}, cv2.IMREAD_UNCHANGED)"
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120).stderr


def test_a_damaged_png_decoded_meanwhile_is_not_the_exif_png_s_note(tmp_path, capfd, monkeypatch):
    with_exif, bad = _pngs(tmp_path)
    assert "libpng error: IDAT" in _alone(bad) and _alone(with_exif) == ""
    import exifread

    with open(with_exif, "rb") as f:
        assert str(exifread.process_file(f, details=False)["Image Make"]) == "Acme"
    started, other_done = threading.Event(), threading.Event()
    decode = cv2.imdecode

    def overlapping(buf, flags):
        if threading.current_thread().name == "exif":
            started.set()
            assert other_done.wait(60)
        return decode(buf, flags)

    monkeypatch.setattr(cv2, "imdecode", overlapping)
    errors: list = []

    def damaged():
        assert started.wait(60)
        try:
            ldr.read_ldr(bad, "png")
        except Exception as exc:  # noqa: BLE001  (the FormatError a damaged PNG gives)
            errors.append(exc)
        other_done.set()

    with warnings.catch_warnings(record=True) as notes:
        warnings.simplefilter("always")
        threads = [threading.Thread(target=lambda: ldr.read_ldr(with_exif, "png"), name="exif"),
                   threading.Thread(target=damaged, name="damaged")]
        for t in threads:
            t.start()
        for t in threads:
            t.join(120)
    assert len(errors) == 1 and "damaged" in str(errors[0])
    assert [str(n.message) for n in notes if "libpng" in str(n.message)] == []
    assert "libpng error: IDAT" in capfd.readouterr().err
