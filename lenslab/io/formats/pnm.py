"""Netpbm PPM (colour), PGM (grey) and PBM (bitmap), binary and ASCII, 8 or 16 bits, sRGB-encoded
(codec: :mod:`lenslab.io.pnm`)."""

from __future__ import annotations

from lenslab.io.plugin import Format, header_only

_WS = b" \t\r\n\x0b\x0c#"


def _magic(kinds: bytes):
    def test(head: bytes) -> bool:
        return (len(head) >= 2 and head[:1] == b"P" and head[1:2] in kinds
                and (len(head) == 2 or head[2:3] in _WS))
    return test


def _read(path, selector=None, raw=False):
    from lenslab.io.pnm import read_pnm

    return read_pnm(path, raw=raw)


def _write(tmp, image, **options):
    import numpy as np

    from lenslab.io.pnm import encode_pnm

    if image.shape[2] == 1 and tmp.suffix.lower() == ".ppm":
        image = np.repeat(image, 3, axis=2)  # a .ppm is colour; grey goes to .pgm (or .pnm)
    tmp.write_bytes(encode_pnm(image, **options))


_OPTIONS = {"bits": "8 (default) or 16", "ascii": "True: P3/P2 text instead of binary",
            "raw": "True: code values / maxval, no sRGB encoding", "dither": "True: TPDF dither before rounding"}


def _declare(path, **options):
    from lenslab.io.pnm import declare_pnm

    return declare_pnm(path, **options)

FORMATS = (
    Format(name="ppm", title="PPM", extensions=(".ppm", ".pnm"), magic=_magic(b"36"), hdr=False, alpha=False,
           channels=(3,), bit_depths=(8, 16), sample_types=("uint",), read=_read, declare=_declare,
           probe=header_only, write=_write,
           read_options=("raw",), write_options=_OPTIONS, note="grey images written as .pnm become PGM; as .ppm, equal R, G, B"),
    Format(name="pgm", title="PGM", extensions=(".pgm",), magic=_magic(b"25"), hdr=False, alpha=False,
           channels=(1,), bit_depths=(8, 16), sample_types=("uint",), read=_read, declare=_declare,
           probe=header_only, write=_write,
           read_options=("raw",), write_options=_OPTIONS),
    Format(name="pbm", title="PBM", extensions=(".pbm",), magic=_magic(b"14"), hdr=False, alpha=False,
           channels=(1,), bit_depths=(1,), sample_types=("uint",), read=_read, declare=_declare,
           probe=header_only, read_options=("raw",),
           note="read only"),
)
