"""The look (exposure, then a tone curve or a display transform) is written once, in the job layer's stage
(:func:`lenslab.jobs.stages.develop`): no command applies a curve, an exposure or a display transform itself,
and compare-tones' panels are what that stage makes of the exposed image."""

from __future__ import annotations

import ast
from pathlib import Path

import cv2
import numpy as np

import lenslab.io as lio
from lenslab.cli.main import main

ROOT = Path(__file__).resolve().parents[2]
#: the look's own functions: only lenslab/jobs (and the tone and io packages that define them) call them
LOOK = {"tonemap", "display_transform", "apply_display", "expose"}


def test_no_command_applies_the_look_itself():
    found = []
    for path in sorted((ROOT / "lenslab" / "cli").rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Call):
                f = node.func
                name = f.attr if isinstance(f, ast.Attribute) else getattr(f, "id", None)
                if name in LOOK:
                    found.append(f"{path.relative_to(ROOT)}:{node.lineno} calls {name}")
    assert found == []


def test_compare_tones_exposes_then_applies_each_curve(tmp_path, capsys):
    x = np.linspace(0.0, 3.0, 48, dtype=np.float32)
    hdr = np.stack([x, x / 2, x / 4], axis=-1)[None].repeat(40, axis=0)  # 40 x 48 ramps
    lio.write(tmp_path / "in.exr", hdr, pixel_type="float")
    out = tmp_path / "strip.png"
    assert main(["compare-tones", str(tmp_path / "in.exr"), "-o", str(out), "--curves", "clamp,reinhard",
                 "--exposure", "1", "--no-dither", "--panel-width", "0", "-q"]) == 0
    strip = cv2.imread(str(out), cv2.IMREAD_UNCHANGED)[..., ::-1].astype(np.float64)  # RGB 8-bit codes
    assert strip.shape == (40, 2 * 48 + 4, 3)
    e = hdr.astype(np.float64) * 2.0  # one stop
    srgb = lambda v: np.where(v <= 0.0031308, 12.92 * v, 1.055 * v ** (1 / 2.4) - 0.055)  # noqa: E731 (IEC 61966-2-1)
    below = slice(30, 40)  # under the labels
    # clamp: min(x, 1); Reinhard (2002, eq. 3): x / (1 + x); within one code (float32 work, rounding to 8 bits)
    np.testing.assert_allclose(strip[below, :48], np.round(srgb(np.clip(e, 0, 1)) * 255)[below], atol=1.0)
    np.testing.assert_allclose(strip[below, 52:], np.round(srgb(e / (1 + e)) * 255)[below], atol=1.0)
