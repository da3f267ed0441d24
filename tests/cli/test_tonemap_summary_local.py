"""The tonemap summary says how the curve acted: a local operator (OpenCV's drago, mantiuk) always works on
luminance, whatever --per-channel/--luminance say, so the line names it a local operator rather than echo a
mode that did not apply; a curve that takes the mode says which one."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

import lenslab.io as lio


@pytest.mark.parametrize(("curve", "flag", "said"), [("mantiuk", "--per-channel", "a local operator on luminance"),
                                                      ("drago", "--luminance", "a local operator on luminance"),
                                                      ("hable", "--luminance", "luminance"),
                                                      ("hable", "--per-channel", "per-channel")])
def test_the_summary_names_what_acted(tmp_path, curve, flag, said):
    src = tmp_path / "s.exr"
    rng = np.random.default_rng(2)
    lio.write(src, rng.uniform(0.01, 50.0, (16, 32, 3)).astype(np.float32), pixel_type="float")
    out = tmp_path / "o.png"
    run = subprocess.run([sys.executable, "-m", "lenslab", "tonemap", str(src), "-o", str(out), "--curve", curve,
                          flag], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert f"curve {curve} ({said})," in run.stderr
