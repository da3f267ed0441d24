"""An EXR header attribute holding a vector of millions of floats (``floatvector``: 4 bytes a value, OpenEXR's file
layout) is refused in one line before OpenEXR's Python bindings build it (a list of Python floats, 8 times its bytes
and more): a 32 MB file of an 8M-float ``Exif:FocalLength`` took `lenslab info` to 900 MB."""

from __future__ import annotations

import sys

import numpy as np
import pytest

from tests.hostile_run import run

FLOATS = 8 << 20
#: peak resident memory allowed, MB: the interpreter with NumPy, OpenCV and OpenEXR (about 60 MB here) and two
#: copies of the 32 MB file's bytes; the bindings' list alone took 426 MB (/usr/bin/time -v)
BUDGET_MB = 60 + 2 * 4 * FLOATS / 1e6


@pytest.fixture(scope="module")
def vector_exr(tmp_path_factory):
    import OpenEXR

    path = tmp_path_factory.mktemp("vector") / "vector.exr"
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage,
              "Exif:FocalLength": [1.0] * FLOATS}
    OpenEXR.File(header, {"RGB": np.zeros((4, 8, 3), np.float32)}).write(str(path))
    return path


@pytest.mark.parametrize("command", ["info", "warp", "stmap"])
def test_a_huge_vector_attribute_is_one_line_in_bounded_memory(vector_exr, command, tmp_path):
    out = ["--to", "equirect", "--size", "16x8", "-o", str(tmp_path / "o.exr")]
    argv = {"info": [str(vector_exr)], "warp": [str(vector_exr), "--from", "exif", *out],
            "stmap": ["--from", f"exif:photo={vector_exr}", *out]}[command]  # (the photo's lens alone: no pixels read)
    done = run([sys.executable, "-m", "lenslab", command, *argv])
    assert done.returncode == 1, done.stderr[-500:]
    assert len(done.stderr.splitlines()) == 1 and "Exif:FocalLength" in done.stderr, done.stderr[-500:]
    assert done.peak_mb < BUDGET_MB, f"{done.peak_mb:.0f} MB"


def test_a_vector_of_a_real_size_reads(tmp_path):
    import OpenEXR

    import lenslab.io as lio

    path = tmp_path / "small.exr"
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage, "weights": [0.5] * 1000}
    OpenEXR.File(header, {"RGB": np.zeros((4, 8, 3), np.float32)}).write(str(path))
    assert lio.read(path)[1]["attributes"]["weights"] == [0.5] * 1000
