"""An enlarging warp of a source that carries alpha, and one through an ST map, peak at their output's own float32
image: the source's alpha, warped as its last channel, is the output's alpha (no coverage plane of the output's size
beside it), and an ST map is held as its s and t, its source positions made a band of rows at a time, its output
drawn into the channels of the one image written.

Measured as :mod:`tests.jobs.test_warp_enlarging_memory` does: each warp in a child process under the address-space
limit of :mod:`tests.hostile_run`, its peak resident memory (the kernel's ``getrusage``) beyond that of the same warp
into 64 x 32, held to 1.5 times the output's float32 RGBA plus 25 MB. Before (main, load 0.6 to 5.8 on 2 cores):
the RGBA source 187 MB beyond (1.39 times the output, 34 MB more than the RGB source's 153 MB: the coverage plane,
33.5 MB), the ST map 665 MB (4.95 times: the map read into two images of the output's size and turned into float64
positions, colour and alpha joined in a new image). Now: 154 MB for either source, 209 MB for the ST map (1.56 times,
of which the map's s and t are 0.5). No time is measured.
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
BUDGET_MB = 1.5 * OUTPUT_MB + 25.0
#: an RGBA source's warp against an RGB source's of the same size: half the coverage plane it no longer holds
#: (4096 x 2048 float32, 33.5 MB); the sources differ by 0.5 MB
RGBA_OVER_RGB_MB = W * H * 4 / 1e6 / 2


@pytest.fixture(scope="module")
def sources(tmp_path_factory):
    folder = tmp_path_factory.mktemp("own-alpha")
    rng = np.random.default_rng(11)
    rgba = rng.random((256, 512, 4), dtype=np.float32)
    rgba[..., :3] *= rgba[..., 3:] * 4  # premultiplied
    lio.write(folder / "rgb.exr", np.ascontiguousarray(rgba[..., :3]), pixel_type="float")
    lio.write(folder / "rgba.exr", rgba, pixel_type="float")
    return folder


def _peak(argv: list[str]) -> float:
    done = run(LENSLAB + argv + ["-q"])
    assert done.returncode == 0, done.stderr
    return done.peak_mb


def _spec(path):
    import OpenImageIO as oiio

    return oiio.ImageInput.open(str(path)).spec()


def test_an_rgba_source_enlarged_holds_no_coverage_plane(sources, tmp_path):
    peaks = {}
    for name, size in (("rgb", "64x32"), ("rgb", f"{W}x{H}"), ("rgba", f"{W}x{H}")):
        out = tmp_path / f"{name}-{size}.exr"
        peaks[name, size] = _peak(["warp", str(sources / f"{name}.exr"), "-o", str(out), "--to", "equirect", "--size",
                                   size])
    rgb, rgba = (peaks[n, f"{W}x{H}"] - peaks["rgb", "64x32"] for n in ("rgb", "rgba"))
    assert rgba <= BUDGET_MB, f"{rgba:.0f} MB beyond the small warp's peak, budget {BUDGET_MB:.0f} MB"
    assert rgba <= rgb + RGBA_OVER_RGB_MB, f"RGBA source {rgba:.0f} MB, RGB source {rgb:.0f} MB"
    spec = _spec(out)
    assert (spec.width, spec.height, list(spec.channelnames)) == (W, H, ["R", "G", "B", "A"])


def test_an_st_map_enlargement_peaks_near_its_output(sources, tmp_path):
    peaks = {}
    for size in ("64x32", f"{W}x{H}"):
        st = tmp_path / f"st-{size}.exr"
        done = run(LENSLAB + ["stmap", "--from", "equirect", "--to", "equirect", "--size", size, "--source-size",
                              "512x256", "-o", str(st), "-q"])
        assert done.returncode == 0, done.stderr
        out = tmp_path / f"out-{size}.exr"
        peaks[size] = _peak(["warp", str(sources / "rgba.exr"), "-o", str(out), "--stmap", str(st)])
    beyond = peaks[f"{W}x{H}"] - peaks["64x32"]
    assert beyond <= BUDGET_MB, f"{beyond:.0f} MB beyond the small warp's peak, budget {BUDGET_MB:.0f} MB"
    spec = _spec(out)
    assert (spec.width, spec.height, list(spec.channelnames)) == (W, H, ["R", "G", "B", "A"])
