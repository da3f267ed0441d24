"""JPEG: 8-bit sRGB colour or grey through OpenCV (codec: :mod:`lenslab.io.ldr`).

Ultra HDR JPEGs (a gain map in an MPF secondary image) are read as their HDR rendition
(:mod:`lenslab.io.gainmap`); ``photo.jpg:sdr`` reads the SDR base image. ``meta["attributes"]["rendition"]``
says which, and ``["gain_map"]`` the gain map's metadata or why it was not applied (``lenslab info`` shows both).
"""

from __future__ import annotations

from lenslab.io.plugin import Format, header_only, ldr_hooks


_read, _write, _declare = ldr_hooks("jpg")

FORMATS = (Format(
    name="jpg", title="JPEG", extensions=(".jpg", ".jpeg", ".jpe", ".jfif"),
    magic=lambda head: head.startswith(b"\xff\xd8\xff"), hdr=False, alpha=False, channels=(1, 3),
    bit_depths=(8,), sample_types=("uint",), read=_read, declare=_declare,
    probe=header_only, write=_write, read_options=("raw",), selectors=True,
    write_options={"quality": "0..100 (default 95)", "subsampling": "444, 422 or 420 (default 444 at quality >= 90)",
                   "raw": "True: code values / 255, no sRGB encoding", "dither": "True: TPDF dither",
                   "exif": "camera tags {name: value} (lenslab.io.exif), written as an APP1 Exif segment",
                   "bits": "8 only",
                   "icc": "an ICC profile (bytes) written as APP2 segments (the Display P3 display writes one)",
                   "in_place": "True: the code values are made in the image's own memory (the array is overwritten; "
                               "saves an array of the image's size in samples)"},
    note="Ultra HDR: the HDR rendition (gain map applied); FILE:sdr the SDR base image"),)
