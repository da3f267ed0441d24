"""An extended-range display (OpenColorIO's "Display P3 HDR": code values above 1.0, as Apple's EDR) is
refused in one line before any work, for every output: integer files would clip its codes and no file or
video tag says what they are. The premise is PyOpenColorIO's own output for the display, above 1.0 for a
bright scene value."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

PyOpenColorIO = pytest.importorskip("PyOpenColorIO")

import lenslab.io as lio  # noqa: E402

DISPLAY = "Display P3 HDR - Display"


def test_opencolorio_gives_codes_above_one_for_this_display():
    cfg = PyOpenColorIO.Config.CreateFromFile("ocio://studio-config-latest")
    view = cfg.getDefaultView(DISPLAY)
    cpu = cfg.getProcessor("Linear Rec.709 (sRGB)", DISPLAY, view,
                           PyOpenColorIO.TRANSFORM_DIR_FORWARD).getDefaultCPUProcessor()
    px = np.full((1, 1, 3), 16.0, np.float32)
    cpu.applyRGB(px)
    assert px.max() > 1.0  # what a 16-bit PNG would have clipped


@pytest.mark.parametrize("to", ["png", "tiff", "exr", "jpg"])
def test_an_extended_range_display_is_refused_in_one_line(tmp_path, to):
    src = tmp_path / "s.exr"
    lio.write(src, np.full((4, 8, 3), 4.0, np.float32), pixel_type="float")
    out = tmp_path / f"o.{to}"
    run = subprocess.run([sys.executable, "-m", "lenslab", "tonemap", str(src), "-o", str(out), "--display",
                          DISPLAY, "--ocio", "ocio://studio-config-latest"], capture_output=True, text=True)
    assert run.returncode == 2, run.stderr
    lines = run.stderr.splitlines()
    assert len(lines) == 1 and "extended-range" in lines[0] and "ST2084-P3-D65" in lines[0]
    assert not out.exists() and sorted(p.name for p in tmp_path.iterdir()) == ["s.exr"]
