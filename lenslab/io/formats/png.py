"""PNG: 8- or 16-bit sRGB grey, grey+alpha, RGB or RGBA (codec: :mod:`lenslab.io.ldr`, OpenCV; grey+alpha:
:mod:`lenslab.io.png_grey_alpha`)."""

from __future__ import annotations

from lenslab.io.plugin import Format, header_only, ldr_hooks


_read, _write, _declare = ldr_hooks("png")

FORMATS = (Format(
    name="png", title="PNG", extensions=(".png",), magic=lambda head: head.startswith(b"\x89PNG\r\n\x1a\n"),
    hdr=False, alpha=True, channels=(1, 2, 3, 4), bit_depths=(8, 16), sample_types=("uint",), read=_read, declare=_declare,
    probe=header_only,
    write=_write, read_options=("raw",),
    write_options={"bits": "8 (default) or 16", "compression": "zlib level 0..9 (default 1)",
                   "raw": "True: code values / maxval, no sRGB encoding", "dither": "True: TPDF dither",
                   "exif": "camera tags {name: value} (lenslab.io.exif), written as an eXIf chunk",
                   "cicp": "4 H.273 code points for a cICP chunk, e.g. (9, 16, 0, 1): Rec.2100 PQ",
                   "icc": "an ICC profile (bytes) written as an iCCP chunk (the Display P3 display writes one)",
                   "in_place": "True: the code values are made in the image's own memory (the array is overwritten; "
                               "saves an array of the image's size in samples)"},
    note="alpha is stored linear (coverage) with straight colour, sRGB-encoded", straight_alpha=("uint",)),)
