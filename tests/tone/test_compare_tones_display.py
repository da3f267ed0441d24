"""compare-tones --display: a last panel with an OpenColorIO display transform, beside the curves."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

import lenslab.io as lio
from lenslab.cli.main import main

PyOpenColorIO = pytest.importorskip("PyOpenColorIO")


def test_the_display_panel_holds_pyopencolorio_code_values(tmp_path, capsys):
    y, x = np.mgrid[0:64, 0:96].astype(np.float32)
    hdr = np.stack([x / 24, y / 16, (x + y) / 40], axis=-1).astype(np.float32)  # 0..4: over white
    lio.write(tmp_path / "in.exr", hdr, pixel_type="float")
    out = tmp_path / "strip.png"
    assert main(["compare-tones", str(tmp_path / "in.exr"), "-o", str(out), "--curves", "clamp", "--exposure", "1",
                 "--display", "sRGB", "--view", "ACES 2.0 - SDR", "--no-dither", "--panel-width", "0"]) == 0
    assert "ACES 2.0 - SDR" in capsys.readouterr().err
    strip = cv2.imread(str(out), cv2.IMREAD_UNCHANGED)[..., ::-1].astype(np.int64)  # RGB 8-bit codes
    assert strip.shape == (64, 96 * 2 + 4, 3)
    # the reference: PyOpenColorIO's own processor on the exposed image, from its built-in config
    cfg = PyOpenColorIO.Config.CreateFromFile("ocio://default")
    names = list(cfg.getDisplays())
    display = next(d for d in names if d.startswith("sRGB"))
    view = next(v for v in cfg.getViews(display) if v.startswith("ACES 2.0 - SDR"))
    scene_linear = next(c.getName() for c in cfg.getColorSpaces() if "rec.709" in c.getName().lower()
                        and "linear" in c.getName().lower())
    cpu = cfg.getProcessor(PyOpenColorIO.DisplayViewTransform(src=scene_linear, display=display, view=view)
                           ).getDefaultCPUProcessor()
    expect = np.ascontiguousarray(hdr * 2.0, dtype=np.float32)
    cpu.applyRGB(expect)
    codes = np.round(np.clip(expect, 0, 1) * 255).astype(np.int64)
    panel = strip[:, 100:]
    below = slice(40, 64)  # under the label
    # within one code: OpenColorIO's float result rounded here and in lenslab's writer (same rule, float32 inputs)
    assert np.abs(panel[below] - codes[below]).max() <= 1
    # and the clamp panel beside it is the sRGB encoding of the exposed, clipped image
    srgb = np.where(np.clip(hdr * 2, 0, 1) <= 0.0031308, 12.92 * np.clip(hdr * 2, 0, 1),
                    1.055 * np.clip(hdr * 2, 0, 1) ** (1 / 2.4) - 0.055)
    assert np.abs(strip[below, :96] - np.round(srgb[below] * 255)).max() <= 1


@pytest.mark.parametrize("args, message", [
    (["--display", "Rec.2100-PQ"], "the strip is an SDR image"),
    (["--display", "sRGB", "-o", "strip.exr"], "holds display code values"),
    (["--view", "ACES 2.0 - SDR"], "--view goes with --display NAME"),
])
def test_display_panel_usage_errors(tmp_path, capsys, args, message):
    lio.write(tmp_path / "in.pfm", np.ones((8, 16, 3), np.float32))
    out = ["-o", str(tmp_path / "strip.png")] if "-o" not in args else []
    args = [a if a != "strip.exr" else str(tmp_path / a) for a in args]
    assert main(["compare-tones", str(tmp_path / "in.pfm"), *out, *args]) == 2
    assert message in capsys.readouterr().err
    assert not list(tmp_path.glob("strip*"))
