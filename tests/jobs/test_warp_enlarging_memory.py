"""A warp into an output much larger than its source (a panorama enlarged, a photo sent into a panorama) peaks
at its output's own float32 image, not at several copies of it: colour and alpha are drawn into the channels of
the one image written, and EXR halves and PNG codes are made in its memory.

Each warp runs in a child process under the address-space limit of :mod:`tests.hostile_run`; its peak resident
memory (the kernel's ``getrusage``, not lenslab's own count) beyond that of the same warp into a 64 x 32 output
(the interpreter and the modules a warp of that format loads: 28 MB beyond ``lenslab info --formats`` for EXR, 51
MB for PNG with OpenCV), measured the same way in the same test, is held to a budget of bytes worked out here from
the output's size. No time is measured.
"""

from __future__ import annotations

import sys

import numpy as np
import pytest

import lenslab.io as lio
from tests.hostile_run import run

LENSLAB = [sys.executable, "-m", "lenslab"]
#: the output: 4096 x 2048 RGBA float32, 134 MB
W, H = 4096, 2048
OUTPUT_MB = W * H * 4 * 4 / 1e6
#: beyond the output: the source (1.6 MB), a band's working memory, a PNG's compressed file (measured: 1.14 times
#: the output for EXR and TIFF, 1.41 for PNG, 0.98 for JPEG, whose output has no alpha). The copies the warp made before (colour and
#: alpha beside the joined image, then the halves, the 8-bit codes or a float copy; a JPEG's tone curve in a copy
#: of the colour) took 2.7 to 3.1 times it (JPEG: 2.1 times).
BUDGET_MB = 1.5 * OUTPUT_MB + 25.0


@pytest.fixture(scope="module")
def panorama(tmp_path_factory):
    path = tmp_path_factory.mktemp("enlarge") / "pano.exr"
    rng = np.random.default_rng(3)
    lio.write(path, (rng.random((256, 512, 3), dtype=np.float32) * 4).astype(np.float32), pixel_type="float")
    return path


@pytest.mark.parametrize("ext", ["exr", "png", "tif", "jpg"])
def test_an_enlarging_warp_peaks_near_its_output(panorama, tmp_path, ext):
    peaks = {}
    for size in ("64x32", f"{W}x{H}"):
        out = tmp_path / f"{size}.{ext}"
        done = run(LENSLAB + ["warp", str(panorama), "-o", str(out), "--to", "equirect", "--size", size, "-q"])
        assert done.returncode == 0, done.stderr
        peaks[size] = done.peak_mb
    beyond = peaks[f"{W}x{H}"] - peaks["64x32"]
    assert beyond <= BUDGET_MB, f"{ext}: {beyond:.0f} MB beyond the small warp's peak, budget {BUDGET_MB:.0f} MB"
    import OpenImageIO as oiio

    spec = oiio.ImageInput.open(str(out)).spec()  # the whole image written: RGBA (JPEG: RGB) of the size asked
    assert (spec.width, spec.height, spec.nchannels) == (W, H, 3 if ext == "jpg" else 4)


def test_a_stereo_output_peaks_as_a_single_view_of_its_size_does(panorama, tmp_path):
    """A stereo frame's eyes are drawn into the output's own pixels: its peak beyond the small warp's is that of an
    equirect of the same size and format (the kernel's ``getrusage`` for both), give or take 25 MB (the eyes' plans
    and their bands' scratch). Each eye drawn into a buffer of its own and copied in added half the output (69 MB
    here: 1.65 times the output against 1.13)."""
    peaks = {}
    for to, size in (("equirect", "64x32"), ("equirect", f"{W}x{H}"), ("stereo", f"{W}x{H}")):
        out = tmp_path / f"{to}-{size}.exr"
        done = run(LENSLAB + ["warp", str(panorama), "-o", str(out), "--to", to, "--size", size, "-q"])
        assert done.returncode == 0, done.stderr
        peaks[to, size] = done.peak_mb
    single = peaks["equirect", f"{W}x{H}"] - peaks["equirect", "64x32"]
    stereo = peaks["stereo", f"{W}x{H}"] - peaks["equirect", "64x32"]
    assert stereo <= single + 25.0, f"stereo {stereo:.0f} MB beyond the small warp's peak, one view {single:.0f} MB"
    import OpenImageIO as oiio

    spec = oiio.ImageInput.open(str(out)).spec()
    assert (spec.width, spec.height, spec.nchannels) == (W, H, 4)
