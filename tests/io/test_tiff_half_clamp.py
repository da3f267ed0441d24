"""A half TIFF holds what a half EXR holds: finite values beyond half's range are clamped to its largest finite value
(with the same note, counted), never written as infinities a sun of 135 808 would become; a true infinity or NaN of the
image stays as it is. The values are read back by tifffile (an outside reader), the bound is NumPy's float16 maximum."""

from __future__ import annotations

import subprocess
import sys
import warnings

import numpy as np
import pytest

import lenslab.io as lio

tifffile = pytest.importorskip("tifffile")

HALF_MAX = float(np.finfo(np.float16).max)  # 65504, the largest finite half (IEEE 754 binary16)


def _bright():
    image = np.full((4, 6, 3), 0.5, np.float32)
    image[1, 2] = (135808.0, 70000.0, 1.0)  # a sun beyond half's range (city.exr's brightest pixel times 4)
    image[2, 3] = (-90000.0, 2.0, 3.0)
    image[3, 4] = (np.inf, np.nan, 65504.0)
    return image


def test_half_tiff_clamps_as_half_exr_does(tmp_path):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        lio.write(tmp_path / "b.tiff", _bright(), sample_type="half")
    back = tifffile.imread(tmp_path / "b.tiff")
    assert back.dtype == np.float16
    assert back[1, 2].tolist() == [HALF_MAX, HALF_MAX, 1.0]
    assert back[2, 3, 0] == -HALF_MAX
    assert np.isposinf(back[3, 4, 0]) and np.isnan(back[3, 4, 1]) and back[3, 4, 2] == HALF_MAX
    assert np.isfinite(back).sum() == back.size - 2  # only the image's own inf and NaN
    notes = [str(w.message) for w in caught if type(w.message).__name__ == "HalfOverflowWarning"]
    assert len(notes) == 1 and notes[0].startswith("3 value(s) beyond half's range were clamped to +-65504")


def test_convert_to_half_tiff_says_what_it_clamped(tmp_path):
    lio.write(tmp_path / "bright.exr", _bright(), pixel_type="float")
    run = subprocess.run([sys.executable, "-m", "lenslab", "convert", str(tmp_path / "bright.exr"), "-o",
                          str(tmp_path / "half.tiff"), "--pixel-type", "half"], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert "3 value(s) beyond half's range were clamped to +-65504" in run.stderr
    back = tifffile.imread(tmp_path / "half.tiff")
    assert back[1, 2, 0] == HALF_MAX and np.isinf(back).sum() == 1
