"""compare-tones --display on a Display P3 file: the display panel is OpenColorIO's transform of the file's own
colours, those outside sRGB included, as ``tonemap --display`` writes them; only the curves' panels are clipped
to the sRGB gamut (and the note says so once).

Outside values: colour-science decodes the codes on Display P3 (its sRGB curve, its P3 -> BT.709 matrix, in
float64, unclipped) and PyOpenColorIO's built-in config applies the same display and view.
"""

from __future__ import annotations

import io

import cv2
import numpy as np
import pytest

from lenslab.cli.main import main

PyOpenColorIO = pytest.importorskip("PyOpenColorIO")
colour = pytest.importorskip("colour")
from PIL import Image  # noqa: E402

from lenslab.io.colour.icc_build import profile as build_profile  # noqa: E402
from lenslab.io.colour.icc_chunks import png_with_profile  # noqa: E402

W, H = 96, 64
BELOW = slice(40, 64)  # under the panel's label
#: code values: PyOpenColorIO's float result rounded here and by lenslab's writer (1), and lenslab's P3 matrix,
#: from the profile's s15.16 colorants, within 1e-4 of colour-science's (a fraction of a code more)
TOL = 1


def _ocio_codes(linear: np.ndarray) -> np.ndarray:
    cfg = PyOpenColorIO.Config.CreateFromFile("ocio://default")
    display = next(d for d in cfg.getDisplays() if d.startswith("sRGB"))
    view = next(v for v in cfg.getViews(display) if v.startswith("ACES 2.0 - SDR"))
    scene_linear = next(c.getName() for c in cfg.getColorSpaces() if "rec.709" in c.getName().lower()
                        and "linear" in c.getName().lower())
    cpu = cfg.getProcessor(PyOpenColorIO.DisplayViewTransform(src=scene_linear, display=display, view=view)
                           ).getDefaultCPUProcessor()
    out = np.ascontiguousarray(linear, dtype=np.float32)
    cpu.applyRGB(out)
    return np.round(np.clip(out, 0, 1) * 255).astype(np.int64)


def test_the_display_panel_keeps_the_colours_outside_srgb(tmp_path, capsys):
    codes = np.random.default_rng(11).integers(0, 256, (H, W, 3), dtype=np.uint8)
    codes[BELOW, :8] = [0, 255, 0]  # P3 green: far outside sRGB
    buf = io.BytesIO()
    Image.fromarray(codes).save(buf, "PNG")
    src, out = tmp_path / "p3.png", tmp_path / "strip.png"
    src.write_bytes(png_with_profile(buf.getvalue(), build_profile("Display P3")))
    assert main(["compare-tones", str(src), "-o", str(out), "--curves", "clamp", "--exposure", "0", "--display",
                 "sRGB", "--view", "ACES 2.0 - SDR", "--no-dither", "--panel-width", "0"]) == 0
    assert capsys.readouterr().err.count("outside the sRGB gamut") == 1
    strip = cv2.imread(str(out), cv2.IMREAD_UNCHANGED)[..., ::-1].astype(np.int64)
    panel = strip[:, -W:]
    linear = colour.RGB_to_RGB(codes.astype(np.float64) / 255, "Display P3", "ITU-R BT.709", None,
                               apply_cctf_decoding=True)
    want, clipped = _ocio_codes(linear), _ocio_codes(np.maximum(linear, 0))
    assert np.abs(want[BELOW] - clipped[BELOW]).max() > 10  # (the clip would show in this panel)
    assert np.abs(panel[BELOW] - want[BELOW]).max() <= TOL
