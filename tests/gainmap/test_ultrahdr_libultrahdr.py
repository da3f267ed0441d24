"""Google's own decoder as the oracle: libultrahdr (through imagecodecs' ``ultrahdr_decode``) reads the Ultra HDR
JPEGs written here (tests/gainmap/files.py) to the same gain as lenslab.

libultrahdr converts the base's Y'CbCr with its own upsampling and matrix, so its SDR differs from a JPEG
library's (0.4 % median on the Pixel photo); the gain (HDR over SDR, per pixel and channel, with zero offsets)
cancels that. With a gain map at the base's resolution, no sampling differs either, and what is left is
libultrahdr's: its float16 output (each of its HDR and SDR values within 2^-11 relative) and its gain table of
1024 entries over GainMapMin..GainMapMax (``kGainFactorNumEntries``: at most one entry, (max - min) / 1023 stops)."""

from __future__ import annotations

import numpy as np
import pytest

import lenslab.io as lio
from tests.gainmap.files import jpeg, ultrahdr

imagecodecs = pytest.importorskip("imagecodecs")


@pytest.mark.parametrize("channels, gamma", [(1, 1.0), (3, 1.0), (1, 2.0)])
def test_libultrahdr_finds_the_same_gain(tmp_path, channels, gamma):
    if not imagecodecs.ULTRAHDR.available:
        pytest.skip("this imagecodecs was built without libultrahdr")
    rng = np.random.default_rng(channels)
    base = jpeg(rng.integers(40, 256, (64, 96, 3)))
    blocks = rng.integers(0, 256, (8, 12, channels))
    gain = np.kron(blocks, np.ones((8, 8, 1)))  # flat 8 x 8 blocks: coded exactly
    top = 3.0  # (libultrahdr 1.4 does not read per-channel rdf:Seq values: "could not find attribute hdrgm:Version")
    path = tmp_path / "u.jpg"
    blob = ultrahdr(base, jpeg(gain), {"GainMapMin": 0, "GainMapMax": top, "Gamma": gamma, "OffsetSDR": 0,
                                       "OffsetHDR": 0, "HDRCapacityMax": 3})
    path.write_bytes(blob)
    hdr = imagecodecs.ultrahdr_decode(blob)[..., :3].astype(np.float64)
    sdr = imagecodecs.ultrahdr_decode(blob, boost=1.0)[..., :3].astype(np.float64)
    ours, _ = lio.read(path)
    ours_sdr, _ = lio.read(f"{path}:sdr")
    lit = (sdr > 0.01) & (ours_sdr > 0.01)  # float16's relative step holds away from its subnormals
    theirs_log, ours_log = np.log2(hdr / sdr)[lit], np.log2(ours / ours_sdr)[lit]
    tolerance = 2 * np.log2(1 + 2.0 ** -11) + top / 1023 + 1e-6
    assert lit.mean() > 0.9 and np.abs(theirs_log - ours_log).max() <= tolerance, np.abs(theirs_log - ours_log).max()
    assert np.ptp(ours_log) > 1.0  # a gain that varies over stops, not a flat one
