"""Slight negatives (a lossy codec's undershoot) are counted for one line per command; real negatives, NaN
and inf stay per file. The undershoot is made by OpenEXR's own DWAB encoder, not by hand."""

from __future__ import annotations

import subprocess
import sys
import warnings

import numpy as np
import pytest

import lenslab.io as lio
from lenslab import tone
from lenslab.tone.repairs import BLOCK_SLIGHT, SLIGHT, slight, take


def dwab_frames(folder, n=3):
    """Frames of fine bright stripes on black through DWAB: OpenEXR's lossy codec leaves values just below 0
    between the stripes (its DCT ringing), as it does in real panoramas."""
    y, x = np.mgrid[0:64, 0:96].astype(np.float32)
    paths = []
    for i in range(n):
        img = np.repeat((((x + i) % 2) * 5.0)[..., None], 3, -1).astype(np.float32)
        paths.append(lio.write(folder / f"f{i}.exr", img, compression="dwab", pixel_type="half"))
    return paths


@pytest.mark.shared_data
def test_real_dwab_undershoot_is_within_the_stated_bound(shared_data):
    # the eight DWAB panoramas: undershoot down to -0.0039, beyond the absolute bound 2^-10, yet within
    # 2^-5 of the brightest value of its 8 x 8 block (the measurement behind BLOCK_SLIGHT: at most 1.5 %)
    beyond = 0
    for p in sorted((shared_data / "hdri").glob("*.exr")):
        img, meta = lio.read(p)
        assert "DWA" in str(meta["attributes"].get("compression", "")).upper()
        low = float(img.min())
        beyond += low < -SLIGHT
        assert slight(img, low), p.name
    assert beyond >= 4


def test_one_summary_line_for_a_batch_and_no_warning(tmp_path):
    dwab_frames(tmp_path)
    r = subprocess.run([sys.executable, "-W", "error::UserWarning", "-m", "lenslab", "tonemap",
                        *(str(p) for p in sorted(tmp_path.glob("*.exr"))), "-o", str(tmp_path / "out"), "-q"],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    lines = [ln for ln in r.stderr.splitlines() if "negative" in ln]
    assert len(lines) == 1 and "slightly negative" in lines[0] and lines[0].endswith("in 3 files"), r.stderr


def test_real_negatives_nan_and_inf_are_still_per_image():
    take()
    img = np.full((16, 16, 3), 0.5, np.float32)
    img[3, 3, 0] = -0.2  # 40 % of its block's brightest value: negative light, not an undershoot
    with pytest.warns(tone.ToneWarning, match="1 negative value"):
        tone.tonemap(img)
    img[3, 3, 0] = np.nan
    with pytest.warns(tone.ToneWarning, match="1 NaN"):
        tone.tonemap(img)
    assert take()[0] == 0
    img[3, 3, 0] = -4e-4  # DWAB-sized: counted, not warned
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        tone.tonemap(img)
    assert take()[:2] == (1, 1)


def test_the_block_rule_transcribed():
    # 2^-5 of the brightest value of the aligned 8 x 8 block (all channels), else 2^-10 absolute
    img = np.full((16, 16, 3), 0.1, np.float32)
    img[2, 2, 1] = 10.0
    img[5, 6, 0] = -0.3  # same block as 10.0: 3 % of it is 0.3125
    assert slight(img, -0.3)
    img[5, 6, 0] = -0.32
    assert not slight(img, -0.32)
    img[5, 6, 0] = -0.001  # below 2^-10 absolute, and 1 % of the block: slight
    img[12, 12, 2] = -0.002  # a block whose brightest value is 0.1: 3 % is 0.003125
    assert slight(img, -0.002)
    img[12, 12, 2] = -0.004
    assert not slight(img, -0.004)
    assert BLOCK_SLIGHT == 2 ** -5 and SLIGHT == 2 ** -10
