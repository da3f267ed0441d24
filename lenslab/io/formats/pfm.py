"""PFM (portable float map): 32-bit float RGB or grey, rows bottom to top (codec: :mod:`lenslab.io.pfm`)."""

from __future__ import annotations

from lenslab.io.plugin import Format, header_only


def _magic(head: bytes) -> bool:
    return head[:1] == b"P" and head[1:2] in (b"F", b"f")


def _read(path, selector=None):
    from lenslab.io.pfm import read_pfm

    return read_pfm(path)


def _write(tmp, image, **options):
    from lenslab.io.pfm import write_pfm

    write_pfm(tmp, image, **options)


def _declare(path, **options):
    from lenslab.io.pfm import declare_pfm

    return declare_pfm(path, **options)

FORMATS = (Format(
    name="pfm", title="PFM", extensions=(".pfm",), magic=_magic, hdr=True, alpha=False, channels=(1, 3),
    bit_depths=(32,), sample_types=("float",), read=_read, declare=_declare, probe=header_only, write=_write,
    write_options={"byte_order": "little (default) or big", "scale": "the header's scale (never applied)"},
    note="the scale is reported, not applied"),)
