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


def _probe(path) -> dict:
    """The header's variables and the resolution line, as the file spells them."""
    from lenslab.io.rgbe import parse_header

    with open(path, "rb") as f:
        data = f.read(1 << 16)
    attrs, res, _ = parse_header(path, data)
    s1, a1, n1, s2, a2, n2 = res
    return {"header": attrs, "resolution": f"{s1.decode()}{a1.decode()} {n1} {s2.decode()}{a2.decode()} {n2}"}


FORMATS = (Format(
    name="hdr", title="Radiance HDR", extensions=(".hdr", ".pic", ".rgbe"),
    magic=lambda head: head.startswith((b"#?RADIANCE", b"#?RGBE")) or (head.startswith(b"#?") and b"\n" in head),
    hdr=True, alpha=False, channels=(3,), bit_depths=(32,), sample_types=("rgbe",), read=_read, declare=_declare, write=_write,
    probe=_probe, clips_negatives=True,
    write_options={"rle": "True (default): run-length encoded scanlines; False: flat"},
    note="EXPOSURE and COLORCORR divided out; XYZE refused; grey is written as equal R, G, B"),)
