"""A warp without ``--size`` keeps the source's pixels per degree, but never makes an output of more than twice
the source's pixels: a 60-degree 600 x 450 photo into a whole equirect at its own 9.6 pixels per degree would be
3460 x 1730 (22 times its pixels; from a 4000 x 3000 photo, 23064 x 11532). The output is then the largest of the
lens's shape within twice the source's pixels, and one note gives the --size that keeps the resolution.

Expected sizes come from the pinhole's geometry in float64 here: the middle column of a perspective view of
horizontal field f and size W x H spans the vertical field 2 atan(tan(f/2) H/W); its rows over that span are its
pixels per degree. The output size is read back by OpenEXR's own binding.
"""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import OpenEXR
import pytest

from lenslab.io import write


def _warp(tmp_path, source: str, size: tuple[int, int], *extra: str) -> tuple[tuple[int, int], str]:
    src = tmp_path / "src.exr"
    write(src, np.full((size[1], size[0], 3), 0.25, np.float32))
    out = tmp_path / "pano.exr"
    run = subprocess.run([sys.executable, "-m", "lenslab", "warp", str(src), "-o", str(out), "--from", source,
                          "--to", "equirect", *extra], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    with OpenEXR.File(str(out)) as f:
        (x0, y0), (x1, y1) = f.header()["dataWindow"]
    return (int(x1 - x0 + 1), int(y1 - y0 + 1)), run.stderr


def test_a_narrow_photo_into_a_whole_sphere_is_limited_to_twice_its_pixels(tmp_path):
    w, h, fov = 600, 450, 60.0
    vfov = math.degrees(2 * math.atan(math.tan(math.radians(fov / 2)) * h / w))
    rows = round(180 * h / vfov)  # 1730: the source's own resolution
    limit = 2 * w * h
    assert 2 * rows * rows > limit
    kept = math.floor(rows * math.sqrt(limit / (2 * rows * rows)))
    size, err = _warp(tmp_path, f"perspective:fov={fov:g}", (w, h))
    assert size == (2 * kept, kept) and size[0] * size[1] <= limit
    notes = [line for line in err.splitlines() if "--size" in line]
    assert len(notes) == 1 and f"--size {2 * rows}x{rows}" in notes[0], err


def test_a_given_size_is_taken_as_given(tmp_path):
    size, err = _warp(tmp_path, "perspective:fov=60", (600, 450), "--size", "3460x1730")
    assert size == (3460, 1730) and "--size" not in err


@pytest.mark.parametrize("fov", [180, 190])
def test_a_fisheye_into_a_whole_sphere_keeps_its_resolution(tmp_path, fov):
    n = 64
    rows = round(180 * n / fov)  # an equidistant fisheye's middle column spans its whole field
    assert 2 * rows * rows <= 2 * n * n
    size, err = _warp(tmp_path, f"fisheye:fov={fov}", (n, n))
    assert size == (2 * rows, rows) and "--size" not in err
