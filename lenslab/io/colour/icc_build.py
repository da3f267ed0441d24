"""A minimal ICC v4.4 matrix/TRC display profile (ICC.1:2022), written beside a file's codes so that readers
without ``cICP`` (Pillow, most viewers) know what they mean: the Display P3 display's PNG, JPEG and TIFF carry
it. The primaries and white come from colour-science (``RGB_COLOURSPACES``), the colorants are adapted to the
D50 connection space by Bradford, and that adaptation is the ``chad`` tag (ICC.1 Annex G); the three channels
share one ``para`` curve of type 3, IEC 61966-2-1's sRGB curve. About 500 bytes.

>>> from PIL import ImageCms; import io
>>> ImageCms.getProfileDescription(ImageCms.ImageCmsProfile(io.BytesIO(profile("Display P3")))).strip()
'Display P3'
"""

from __future__ import annotations

import functools
import hashlib
import struct

import numpy as np

from lenslab.io.colour.icc import D50

#: IEC 61966-2-1: y = ((x + 0.055) / 1.055) ** 2.4 from x = 0.04045, x / 12.92 below (``para`` type 3: g a b c d)
SRGB_CURVE = (2.4, 1 / 1.055, 0.055 / 1.055, 1 / 12.92, 0.04045)
#: the displays a profile is written for: their colour-science colourspace
SPACES = {"Display P3": "Display P3"}


def _s15(values) -> bytes:
    """s15Fixed16Number values, rounded to nearest."""
    return b"".join(struct.pack(">i", int(round(float(v) * 65536.0))) for v in values)


def _mluc(text: str) -> bytes:
    """A ``multiLocalizedUnicodeType`` tag of one English record."""
    utf16 = text.encode("utf-16-be")
    return b"mluc" + bytes(4) + struct.pack(">II2s2sII", 1, 12, b"en", b"US", len(utf16), 28) + utf16


def _tags(name: str) -> list[tuple[bytes, bytes]]:
    from lenslab.srgb import colour_science

    colour = colour_science()

    space = colour.RGB_COLOURSPACES[SPACES[name]]
    white = colour.xy_to_XYZ(space.whitepoint)
    chad = colour.adaptation.matrix_chromatic_adaptation_VonKries(white, np.asarray(D50), "Bradford")
    npm = colour.normalised_primary_matrix(space.primaries, space.whitepoint)  # RGB -> XYZ, white Y = 1
    colorants = chad @ npm
    curve = b"para" + bytes(4) + struct.pack(">H", 3) + bytes(2) + _s15(SRGB_CURVE)
    return [(b"desc", _mluc(name)), (b"cprt", _mluc("No copyright, use freely")),
            (b"wtpt", b"XYZ " + bytes(4) + _s15(D50)), (b"chad", b"sf32" + bytes(4) + _s15(chad.reshape(-1))),
            (b"rXYZ", b"XYZ " + bytes(4) + _s15(colorants[:, 0])), (b"gXYZ", b"XYZ " + bytes(4) + _s15(colorants[:, 1])),
            (b"bXYZ", b"XYZ " + bytes(4) + _s15(colorants[:, 2])),
            (b"rTRC", curve), (b"gTRC", curve), (b"bTRC", curve)]


@functools.lru_cache(maxsize=4)
def profile(name: str = "Display P3") -> bytes:
    """The profile of display ``name`` (a key of :data:`SPACES`) as bytes, its ID the MD5 of ICC.1 7.2.18."""
    tags = _tags(name)
    table_end = 128 + 4 + 12 * len(tags)
    entries, body, placed = [], b"", {}
    for sig, data in tags:
        if data not in placed:  # the three channels share one curve
            placed[data] = table_end + len(body)
            body += data + bytes(-len(data) % 4)
        entries.append(struct.pack(">4sII", sig, placed[data], len(data)))
    size = table_end + len(body)
    header = (struct.pack(">I4sI4s4s4s", size, b"\0\0\0\0", 0x04400000, b"mntr", b"RGB ", b"XYZ ")
              + struct.pack(">6H", 2025, 1, 1, 0, 0, 0) + b"acsp" + bytes(4) + bytes(4) + bytes(4) + bytes(4)
              + bytes(8) + struct.pack(">I", 0) + _s15(D50) + bytes(4))
    header += bytes(128 - len(header))
    data = bytearray(header + struct.pack(">I", len(tags)) + b"".join(entries) + body)
    digest = hashlib.md5(bytes(data[:44]) + bytes(4) + bytes(data[48:64]) + bytes(4) + bytes(data[68:84])
                         + bytes(16) + bytes(data[100:])).digest()
    data[84:100] = digest
    return bytes(data)


def display_profile(points) -> bytes:
    """The profile of an SDR display's cICP code points (P3-D65 primaries 12, sRGB transfer 13 or BT.709's 1)."""
    if points[0] != 12 or points[1] not in (1, 13):
        raise ValueError(f"no ICC profile is written for cICP code points {tuple(points)}")
    return profile("Display P3")
