"""Radiance RGBE ``.hdr``: shared-exponent linear RGB, flat or run-length encoded (codec: :mod:`lenslab.io.rgbe`)."""

from __future__ import annotations

from lenslab.io.plugin import Format


def _read(path, selector=None):
    from lenslab.io.rgbe import read_hdr

    return read_hdr(path)


def _write(tmp, image, rle=True):
    from lenslab.io.rgbe import encode_hdr

    tmp.write_bytes(encode_hdr(image, rle=rle))



def _declare(path, **options):
    from lenslab.io.rgbe import declare_hdr

    return declare_hdr(path, **options)

FORMATS = (Format(
    name="hdr", title="Radiance HDR", extensions=(".hdr", ".pic", ".rgbe"),
    magic=lambda head: head.startswith((b"#?RADIANCE", b"#?RGBE")) or (head.startswith(b"#?") and b"\n" in head),
    hdr=True, alpha=False, channels=(1, 3), bit_depths=(32,), sample_types=("rgbe",), read=_read, declare=_declare, write=_write,
    write_options={"rle": "True (default): run-length encoded scanlines; False: flat"},
    note="EXPOSURE and COLORCORR divided out; XYZE refused"),)
