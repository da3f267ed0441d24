"""An ISO 21496-1 block of the backward direction (flags 0x04: the base image is the HDR rendition, the gain map
leads down to SDR). Its base headroom is then the HDR one and its alternate headroom SDR's (0): the base's
headroom above the alternate's, as ISO 21496-1 and libavif (``avifGetGainMapWeight``) read it. libultrahdr refuses
such a JPEG ("hdr intent as base rendition is not supported"); lenslab reads the base as it is and says why,
not that its headrooms are reversed."""

from __future__ import annotations

import numpy as np

from lenslab.io.gainmap import iso
from tests.gainmap.files import iso_21496, jpeg, ultrahdr
from tests.gainmap.test_iso21496_hostile import _libultrahdr_refuses
from tests.gainmap.test_ultrahdr_hostile import _base, _read_noted

#: base (HDR) headroom 2 stops, alternate (SDR) headroom 0
BACKWARD = iso_21496(gmin=-2.0, gmax=0.0, gamma=1.0, off_sdr=1 / 64, off_hdr=1 / 64, cap_min=2.0, cap_max=0.0,
                     flags=0x44, denominator=64)


def test_a_backward_block_is_read_as_an_hdr_base_as_libultrahdr_refuses_to_map_it(tmp_path):
    path = tmp_path / "b.jpg"
    path.write_bytes(ultrahdr(_base(), jpeg(np.full((8, 16), 200)), None, iso=BACKWARD,
                              iso_version=b"\x00\x00\x00\x00"))
    note = _read_noted(path)[1]
    assert "its base image is the HDR rendition" in note and "not 0 <= min <= max" not in note
    assert _libultrahdr_refuses(path.read_bytes())


def test_a_backward_blocks_headrooms_are_the_range_the_map_applies_over():
    """HDRCapacityMin and HDRCapacityMax (the hdrgm XMP's, log2) span the two headrooms whichever is the base's."""
    meta = iso.parse(BACKWARD)
    assert meta.base_is_hdr and (meta.hdr_capacity_min, meta.hdr_capacity_max) == (0.0, 2.0)
