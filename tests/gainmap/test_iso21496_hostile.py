"""Damaged and hostile ISO 21496-1 blocks: the base image is read with one note that says why (as for damaged
``hdrgm`` XMP), never a crash or a value no gain map can mean. The blocks are written from libultrahdr's layout
(tests/gainmap/files.py ``iso_21496``); where libultrahdr's decoder refuses the same file, it is asked too."""

from __future__ import annotations

import struct

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import lenslab.io as lio
from lenslab.io.gainmap import iso
from lenslab.io.gainmap.metadata import MetadataError
from tests.gainmap.files import iso_21496, jpeg, ultrahdr
from tests.gainmap.test_ultrahdr_hostile import GOOD, _base, _read_noted, read_or_refused

VALUES = dict(gmin=0.0, gmax=2.0, gamma=1.0, off_sdr=1 / 64, off_hdr=1 / 64, cap_min=0.0, cap_max=2.0)
#: a good block, one denominator per value (0x40: the base's colour space): 5 + 16 + 40 bytes
BLOCK = iso_21496(**VALUES, flags=0x40, denominator=64)


def _file(block: bytes | None, version: bytes | None = b"\x00\x00\x00\x00", xmp: dict | None = None) -> bytes:
    return ultrahdr(_base(), jpeg(np.full((8, 16), 200)), xmp, iso=block, iso_version=version)


def _libultrahdr_refuses(blob: bytes) -> bool:
    imagecodecs = pytest.importorskip("imagecodecs")
    if not imagecodecs.ULTRAHDR.available:
        pytest.skip("this imagecodecs was built without libultrahdr")
    try:
        imagecodecs.ultrahdr_decode(blob)
    except Exception:  # imagecodecs' UltrahdrError: the decoder refused the metadata
        return True
    return False


def _with(offset: int, value: bytes) -> bytes:
    return BLOCK[:offset] + value + BLOCK[offset + len(value):]


# offsets in BLOCK: versions 0..4, flags 4, headrooms 5..21 (N, D, N, D), then min N/D 21, max 29, gamma 37, ...
CASES = {
    "minimum version 1": (_with(0, b"\x00\x01"), "needs a reader of version 1", True),
    "a denominator of 0": (_with(33, b"\x00\x00\x00\x00"), "GainMapMax has a denominator of 0", True),
    "gamma 0": (_with(37, b"\x00\x00\x00\x00"), "its Gamma is 0", True),
    "a boost of 2^(2^31 - 1)": (_with(29, b"\x7f\xff\xff\xff\x00\x00\x00\x01"), "beyond 2^64", False),
    "max below min": (_with(21, struct.pack(">i", 64 * 3)), "below its GainMapMin", False),
    "capacities reversed": (_with(5, struct.pack(">I", 64 * 3)), "are not 0 <= min <= max", False),
    "an offset of -3": (_with(45, struct.pack(">i", -64 * 3)), "beyond +-1", False),
    "HDR base (backward direction)": (_with(4, b"\x44"), "its base image is the HDR rendition", True),
}


@pytest.mark.parametrize("case", list(CASES))
def test_a_hostile_block_leaves_the_base_with_a_note(tmp_path, case):
    block, words, libultrahdr_refuses = CASES[case]
    path = tmp_path / "h.jpg"
    path.write_bytes(_file(block))
    assert words in _read_noted(path)[1]
    if libultrahdr_refuses:  # its own checks (gainmapmetadata.cpp) refuse these too
        assert _libultrahdr_refuses(path.read_bytes())


def test_a_block_cut_anywhere_leaves_the_base_with_a_note(tmp_path):
    path = tmp_path / "cut.jpg"
    for size in range(0, len(BLOCK)):
        path.write_bytes(_file(BLOCK[:size]))
        if size == 0:  # an empty block: libultrahdr skips it, and the gain map has no other metadata
            assert "carries hdrgm or ISO 21496-1 metadata" in _read_noted(path)[1]
        else:
            assert "cut short" in _read_noted(path)[1], size
    path.write_bytes(_file(BLOCK))
    image, meta = lio.read(path)
    assert "metadata from its ISO 21496-1 block" in meta["attributes"]["gain_map"]


def test_a_damaged_block_beside_good_xmp_is_refused_as_libultrahdr_refuses_it(tmp_path):
    """libultrahdr reads the ISO block where there is one (``JpegR::parseGainMapMetadata``) and fails on a
    damaged one, whatever the XMP says: lenslab reads the base, with a note."""
    path = tmp_path / "both.jpg"
    path.write_bytes(_file(BLOCK[:-3], xmp=GOOD))
    assert "cut short" in _read_noted(path)[1] and _libultrahdr_refuses(path.read_bytes())


def test_a_damaged_icc_profile_of_the_alternate_colour_space_leaves_the_base_with_a_note(tmp_path):
    """Flags 0x80 (values per channel, the gain applies in the alternate image's colour space): the gain map
    image's ICC profile names that space; one that is 64 bytes of nothing is refused."""
    rgb = jpeg(np.random.default_rng(4).integers(0, 256, (8, 16, 3)))
    icc = b"ICC_PROFILE\x00\x01\x01" + bytes(64)
    damaged = rgb[:2] + b"\xff\xe2" + struct.pack(">H", len(icc) + 2) + icc + rgb[2:]
    block = iso_21496(**{**VALUES, "gmax": [2.0, 2.5, 3.0]}, flags=0x80)
    path = tmp_path / "icc.jpg"
    path.write_bytes(ultrahdr(_base(), damaged, None, iso=block, iso_version=b"\x00\x00\x00\x00"))
    assert "its gain map image: the embedded ICC profile" in _read_noted(path)[1]


def test_the_primary_images_version_block_must_allow_version_0(tmp_path):
    path = tmp_path / "v.jpg"
    path.write_bytes(_file(BLOCK, version=b"\x00\x02\x00\x05"))
    assert "needs a reader of version 2" in _read_noted(path)[1]
    path.write_bytes(_file(BLOCK, version=b"\x00"))
    assert "cut short" in _read_noted(path)[1]
    path.write_bytes(_file(BLOCK, version=None))  # no version block: the gain map's own block is read
    assert "metadata from its ISO 21496-1 block" in lio.read(path)[1]["attributes"]["gain_map"]


@settings(max_examples=300, deadline=None, derandomize=True)
@given(st.binary(max_size=200))
def test_any_bytes_parse_or_are_refused_in_one_line(payload):
    """Whatever bytes the block holds: metadata :func:`lenslab.io.gainmap.metadata.check` accepts, or a
    MetadataError of one line."""
    try:
        meta = iso.parse(payload)
    except MetadataError as exc:
        assert "\n" not in str(exc)
        return
    assert all(np.isfinite(v).all() for v in (meta.gain_map_min, meta.gain_map_max, meta.gamma))
    assert min(meta.gamma) > 0 and all(lo <= hi for lo, hi in zip(meta.gain_map_min, meta.gain_map_max))


_GOOD_FILE = _file(iso_21496(gmin=[0, 0.1, 0.2], gmax=[2, 2.5, 3], gamma=[1, 2, 0.5], off_sdr=0, off_hdr=0,
                             cap_min=0, cap_max=3, flags=0xC8))


@settings(max_examples=150, deadline=None, derandomize=True)
@given(st.lists(st.tuples(st.integers(0, 80), st.integers(0, 255)), min_size=1, max_size=4))
def test_any_damage_to_the_block_reads_or_is_refused(tmp_path_factory, changes):
    """Bytes of the gain map's block changed (its flags, versions, rationals): a finite float32 image (the HDR
    rendition, or the base with a note), never another exception."""
    blob = bytearray(_GOOD_FILE)
    start = blob.rindex(b"urn:iso:std:iso:ts:21496:-1\x00") + 28
    for at, value in changes:
        if start + at < len(blob):
            blob[start + at] = value
    path = tmp_path_factory.mktemp("iso") / "d.jpg"
    path.write_bytes(bytes(blob))
    attributes = read_or_refused(path)
    assert attributes is None or attributes["rendition"].split(":")[0] in ("HDR", "SDR base image", "HDR base image")
