"""Options of ``lenslab warp`` that cannot apply are usage errors (exit 2, one line), never ignored."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

import lenslab.io as lio


def run(*args):
    return subprocess.run([sys.executable, "-m", "lenslab", "warp", *map(str, args)], capture_output=True, text=True)


@pytest.fixture()
def pano(tmp_path):
    return lio.write(tmp_path / "p.exr", np.random.default_rng(0).random((32, 64, 3)).astype(np.float32) * 4)


@pytest.mark.parametrize("extra,out,says", [
    (["--tone", "aces", "--display", "sRGB"], "a.png", "--tone and --display"),
    (["--tone", "aces"], "a.exr", "--tone applies to display formats"),
    (["--tone", "reinhard"], "a.tif", "--tone applies to display formats"),
    (["--frames", "0:2"], "a.png", "--frames picks frames of a video"),
    (["--from", "equirect", "--from", "fisheye:fov=180"], "a.png", "--from given twice"),
    (["--to", "fisheye", "--to", "perspective"], "a.png", "--to given twice"),
])
def test_options_that_cannot_apply_are_usage_errors(tmp_path, pano, extra, out, says):
    args = [pano, "-o", tmp_path / out, "--size", "32x32", *extra]
    if "--to" not in extra:
        args += ["--to", "fisheye:fov=180"]
    r = run(*args)
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and says in lines[0]
    assert not (tmp_path / out).exists()


def test_tone_on_a_display_output_is_applied(tmp_path, pano):
    outs = {}
    for curve in ("aces", "clamp"):
        r = run(pano, "-o", tmp_path / f"{curve}.png", "--to", "fisheye:fov=180", "--size", "32x32", "--tone", curve)
        assert r.returncode == 0, r.stderr
        outs[curve] = lio.read(tmp_path / f"{curve}.png", raw=True)[0]
    assert np.abs(outs["aces"] - outs["clamp"]).max() > 0.1  # the curve made a difference


@pytest.mark.parametrize("argv,says", [
    (["convert", "{p}", "--to", "exr", "-o", "{d}/c.exr", "--tone", "aces"], "--tone applies to display formats"),
    (["convert", "{p}", "--to", "png", "-o", "{d}/c.png", "--tone", "aces", "--display", "sRGB"],
     "--tone and --display"),
    (["convert", "{p}", "--to", "png", "-o", "{d}/c.png", "--frames", "0:2"], "--frames picks frames of a video"),
    (["tonemap", "{p}", "-o", "{d}/t.png", "--curve", "aces", "--display", "sRGB"], "--curve and --display"),  # named as typed
])
def test_convert_and_tonemap_refuse_the_same(tmp_path, pano, argv, says):
    args = [a.format(p=pano, d=tmp_path) for a in argv]
    r = subprocess.run([sys.executable, "-m", "lenslab", *args], capture_output=True, text=True)
    assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1 and says in r.stderr
