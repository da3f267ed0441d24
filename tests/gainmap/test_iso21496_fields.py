"""ISO 21496-1 blocks written here from libultrahdr's layout (tests/gainmap/files.py ``iso_21496``) with what its
encoder never writes (values per channel, offsets, a gamma, a common denominator or one per value), read by
lenslab to the gain libultrahdr's decoder (imagecodecs' ``ultrahdr_decode``) finds in the same file; and the
choice between an ISO block and ``hdrgm`` XMP that disagree, as libultrahdr makes it.

Base and gain map carry no ICC profile (both decoders take sRGB primaries) and the gain map has the base's size
in flat 8 x 8 blocks (coded exactly, sampled alike). The gain per channel is ``(HDR + OffsetHDR) / (SDR +
OffsetSDR)``; with libultrahdr's SDR from ``boost=1`` (weight 0: ``SDR + OffsetSDR - OffsetHDR``) its own is
``(HDR + OffsetHDR) / (SDR_1 + OffsetHDR)``. Tolerance, in stops: its float16 output (2^-11 of each value; an
offset added to a positive value keeps that bound) for both, and one entry of its 1024-entry gain table per
channel ((max - min) / 1023)."""

from __future__ import annotations

import numpy as np
import pytest

import lenslab.io as lio
from tests.gainmap.files import iso_21496, jpeg, ultrahdr

imagecodecs = pytest.importorskip("imagecodecs")
if not imagecodecs.ULTRAHDR.available:
    pytest.skip("this imagecodecs was built without libultrahdr", allow_module_level=True)

PER_CHANNEL = dict(gmin=[-0.5, 0.0, 0.25], gmax=[2.0, 3.0, 2.5], gamma=[1.0, 2.0, 0.5],
                   off_sdr=[1 / 64, 1 / 32, 0.0], off_hdr=[1 / 64, 0.0, 1 / 128], cap_min=0.0, cap_max=3.0)
COMMON = dict(gmin=0.0, gmax=2.5, gamma=1.5, off_sdr=1 / 64, off_hdr=1 / 64, cap_min=0.0, cap_max=2.5)


def _file(channels: int, iso: bytes, xmp: dict | None = None, seed: int = 1) -> bytes:
    rng = np.random.default_rng(seed)
    base = jpeg(rng.integers(40, 256, (64, 96, 3)))
    gain = np.kron(rng.integers(0, 256, (8, 12, channels)), np.ones((8, 8, 1)))  # flat 8 x 8 blocks
    return ultrahdr(base, jpeg(gain), xmp, iso=iso, iso_version=b"\x00\x00\x00\x00")


def _gains(blob: bytes, path, off_sdr, off_hdr):
    """(libultrahdr's log2 gain, lenslab's, the pixels compared): see the module docstring."""
    path.write_bytes(blob)
    o_sdr, o_hdr = np.broadcast_to(off_sdr, (3,)), np.broadcast_to(off_hdr, (3,))
    hdr = imagecodecs.ultrahdr_decode(blob)[..., :3].astype(np.float64)
    sdr = imagecodecs.ultrahdr_decode(blob, boost=1.0)[..., :3].astype(np.float64)
    ours, meta = lio.read(path)
    ours_sdr, _ = lio.read(f"{path}:sdr")
    keep = (sdr.min(axis=2) > 0.01) & (ours_sdr.min(axis=2) > 0.01) & (hdr.min(axis=2) > 0.01)
    theirs = np.log2((hdr + o_hdr) / (sdr + o_hdr))
    mine = np.log2((ours.astype(np.float64) + o_hdr) / (ours_sdr.astype(np.float64) + o_sdr))
    return theirs, mine, keep, meta


@pytest.mark.parametrize("flags", [0xC0, 0xC8], ids=["a denominator per value", "a common denominator"])
def test_per_channel_values_offsets_and_gamma_read_as_libultrahdr_reads_them(tmp_path, flags):
    blob = _file(3, iso_21496(**PER_CHANNEL, flags=flags, denominator=1 << 16))
    theirs, mine, keep, meta = _gains(blob, tmp_path / "p.jpg", PER_CHANNEL["off_sdr"], PER_CHANNEL["off_hdr"])
    steps = (np.subtract(PER_CHANNEL["gmax"], PER_CHANNEL["gmin"])) / 1023
    tolerance = 2 * np.log2(1 + 2.0 ** -11) + steps + 1e-6
    assert keep.mean() > 0.9
    assert (np.abs(theirs - mine) <= tolerance)[keep].all(), np.abs(theirs - mine)[keep].max(axis=0)
    assert np.ptp(mine[keep], axis=0).min() > 1.0  # the gains vary over stops in every channel
    assert "GainMapMax (2, 3, 2.5)" in meta["attributes"]["gain_map"]


def test_one_value_for_all_channels_is_read_for_each(tmp_path):
    blob = _file(1, iso_21496(**COMMON, flags=0x48, denominator=1000))
    theirs, mine, keep, _ = _gains(blob, tmp_path / "c.jpg", COMMON["off_sdr"], COMMON["off_hdr"])
    tolerance = 2 * np.log2(1 + 2.0 ** -11) + COMMON["gmax"] / 1023 + 1e-6
    assert keep.mean() > 0.9 and (np.abs(theirs - mine) <= tolerance)[keep].all()
    assert np.ptp(mine[keep]) > 1.0


def test_the_iso_block_wins_over_disagreeing_xmp_as_in_libultrahdr(tmp_path):
    """libultrahdr's ``JpegR::parseGainMapMetadata`` takes the gain map image's ISO block where it has one: the
    XMP says GainMapMax 1, the block 2.5; both decoders boost by the block's values, and ``info`` names the
    difference."""
    xmp = {"GainMapMin": 0, "GainMapMax": 1, "Gamma": 1.5, "OffsetSDR": 1 / 64, "OffsetHDR": 1 / 64,
           "HDRCapacityMax": 2.5}
    blob = _file(1, iso_21496(**COMMON, flags=0x40), xmp=xmp)
    theirs, mine, keep, meta = _gains(blob, tmp_path / "x.jpg", COMMON["off_sdr"], COMMON["off_hdr"])
    tolerance = 2 * np.log2(1 + 2.0 ** -11) + COMMON["gmax"] / 1023 + 1e-6
    assert (np.abs(theirs - mine) <= tolerance)[keep].all() and mine[keep].max() > 2.0  # beyond the XMP's 2^1
    note = meta["attributes"]["gain_map"]
    assert note.endswith("metadata from its ISO 21496-1 block (libultrahdr's choice); its hdrgm XMP disagrees: "
                         "GainMapMax 1 in the XMP against 2.5")  # the one field that differs


def test_xmp_that_agrees_is_said_to(tmp_path):
    xmp = {"GainMapMin": 0, "GainMapMax": 2.5, "Gamma": 1.5, "OffsetSDR": 0.015625, "OffsetHDR": 0.015625,
           "HDRCapacityMax": 2.5}
    path = tmp_path / "a.jpg"
    path.write_bytes(_file(1, iso_21496(**COMMON, flags=0x40), xmp=xmp))
    assert lio.read(path)[1]["attributes"]["gain_map"].endswith("metadata from its ISO 21496-1 block; its hdrgm "
                                                                "XMP agrees")


def test_the_pixel_photo_has_no_iso_block_and_reads_from_its_xmp(shared_data):
    """The corpus photo (formats/oiio-images/ultrahdr_sky.jpg) holds ``hdrgm`` XMP only: its note is the XMP's
    values as printed in the file (GainMapMax 2.205275, offsets 0, no Gamma), with no word of another source."""
    path = shared_data / "formats/oiio-images/ultrahdr_sky.jpg"
    assert b"urn:iso:std:iso:ts:21496" not in path.read_bytes()
    assert lio.read(path)[1]["attributes"]["gain_map"] == (
        "1020 x 768, 1 channel(s); GainMapMin 0, GainMapMax 2.205 (log2), Gamma 1, OffsetSDR 0, OffsetHDR 0, "
        "HDRCapacityMin 0, HDRCapacityMax 2.205: headroom 2.21 stops (4.61x SDR white)")
