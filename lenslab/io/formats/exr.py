"""OpenEXR: linear half/float/uint channels, parts, layers, any compression (codec: :mod:`lenslab.io.exr`)."""

from __future__ import annotations

from lenslab.io.plugin import Format


def _read(path, selector=None, data_window=False, rec709=True):
    from lenslab.io.exr import read_exr

    return read_exr(path, selector, data_window=data_window, rec709=rec709)


def _write(tmp, image, **options):
    from lenslab.io.exr import write_exr

    write_exr(tmp, image, **options)



def _declare(path, **options):
    from lenslab.io.exr_chunks import declare_exr

    return declare_exr(path, **options)

FORMATS = (Format(
    name="exr", title="OpenEXR", extensions=(".exr",), magic=lambda head: head.startswith(b"\x76\x2f\x31\x01"),
    hdr=True, alpha=True, channels=(1, 2, 3, 4), bit_depths=(16, 32), sample_types=("half", "float", "uint"),
    read=_read, declare=_declare, write=_write, read_options=("data_window", "rec709"),
    write_options={"pixel_type": "half or float (default half)",
                   "compression": "zip (default), piz, zips, rle, none, pxr24, b44, b44a, dwaa, dwab, zstd, ...",
                   "channels": "channel names, for images that are not Y, RGB or RGBA",
                   "attributes": "header attributes {name: value}",
                   "threads": "codec threads (default: one per core)"},
    selectors=True, camera=True,
    compressions=("none", "rle", "zips", "zip", "piz", "pxr24", "b44", "b44a", "dwaa", "dwab", "zstd", "htj2k256",
                  "htj2k32"),
    note="multi-part and layered files; luminance/chroma and other primaries converted to Rec.709"),)
