"""A half-float TIFF is made in the memory of the image its command gives up (``convert``, ``warp``): its peak is the
float TIFF's, not the float image and a float16 copy of it; the samples are NumPy's cast of the float32 image, as
tifffile reads them back.

Measured as :mod:`tests.jobs.test_warp_enlarging_memory` does (each command in a child process under the
address-space limit, its peak resident memory by the kernel's ``getrusage``, beyond the same command on a 64 x 32
image). Before (main, load 3.8 to 4.0 on 2 cores), converting a 4096 x 2048 RGB float EXR (101 MB decoded) peaked
160 MB beyond for the half TIFF against 113 MB for the float TIFF (the float16 copy: 50 MB); now 111 MB and 115 MB.
No time is measured.
"""

from __future__ import annotations

import sys

import numpy as np
import pytest

import lenslab.io as lio
from tests.hostile_run import run

tifffile = pytest.importorskip("tifffile")

LENSLAB = [sys.executable, "-m", "lenslab"]
W, H = 4096, 2048
#: half of the float16 copy of the image (4096 x 2048 x 3 x 2 bytes, 50 MB) the half TIFF was made in before
HALF_COPY_MB = W * H * 3 * 2 / 1e6 / 2


def _image(h, w):
    y = np.linspace(0.0, 4.0, h, dtype=np.float32)[:, None, None]
    x = np.linspace(0.0, 1.0, w, dtype=np.float32)[None, :, None]
    noise = np.random.default_rng(2).random((h, w, 3), dtype=np.float32) * 0.01
    return y * (0.5 + x) * np.array([1.0, 0.8, 0.6], np.float32) + noise


def test_a_half_tiff_peaks_as_the_float_tiff_does(tmp_path):
    for name, (h, w) in (("small", (32, 64)), ("big", (H, W))):
        lio.write(tmp_path / f"{name}.exr", _image(h, w), pixel_type="float")
    beyond = {}
    for pixel in ("half", "float"):
        peaks = {}
        for name in ("small", "big"):
            out = tmp_path / f"{name}-{pixel}.tif"
            done = run(LENSLAB + ["convert", str(tmp_path / f"{name}.exr"), "-o", str(out), "--pixel-type", pixel,
                                  "-q"])
            assert done.returncode == 0, done.stderr
            peaks[name] = done.peak_mb
        beyond[pixel] = peaks["big"] - peaks["small"]
    assert beyond["half"] <= beyond["float"] + HALF_COPY_MB, beyond
    with tifffile.TiffFile(tmp_path / "big-half.tif") as tif:
        assert tif.pages[0].dtype == np.float16 and tif.pages[0].shape == (H, W, 3)


def test_half_samples_are_numpys_cast_of_the_image(tmp_path):
    image = _image(48, 80)
    image[0, 0] = [70000.0, -70000.0, 65519.0]  # past half's range: infinite, as NumPy casts them
    image[1, 1] = [1.0 / 3.0, 6e-8, -2.0 ** -24]  # rounded to nearest even, subnormals
    lio.write(tmp_path / "in.exr", image, pixel_type="float")
    out = tmp_path / "out.tif"
    from lenslab.cli.main import main

    assert main(["convert", str(tmp_path / "in.exr"), "-o", str(out), "--pixel-type", "half", "-q"]) == 0
    got = tifffile.imread(out)
    assert got.dtype == np.float16
    with np.errstate(over="ignore"):
        want = image.astype(np.float16)
    np.testing.assert_array_equal(got.view(np.uint16), want.view(np.uint16))
    assert np.isinf(got[0, 0, :2]).all() and float(got[1, 1, 0]) == 0.333251953125
