"""`lenslab warp` of an EXR with channels besides colour and alpha (depth ``Z``, normals ``N.x``...) writes
colour and alpha only and says so in one note line naming each channel left out. Expected values:
OpenImageIO's channel names of the source and of the output."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

oiio = pytest.importorskip("OpenImageIO")
OpenEXR = pytest.importorskip("OpenEXR")


def _names(path) -> list[str]:
    inp = oiio.ImageInput.open(str(path))
    names = list(inp.spec().channelnames)
    inp.close()
    return names


@pytest.fixture
def layered(tmp_path):
    rng = np.random.default_rng(2)
    h, w = 16, 32
    chans = {c: rng.uniform(0, 2, (h, w)).astype(np.float32) for c in "RGB"}
    chans["Z"] = rng.uniform(1, 1e3, (h, w)).astype(np.float32)
    for c in ("N.x", "N.y", "N.z"):
        chans[c] = rng.uniform(-1, 1, (h, w)).astype(np.float16)
    path = tmp_path / "pano.exr"
    OpenEXR.File({"type": OpenEXR.scanlineimage, "compression": OpenEXR.ZIP_COMPRESSION}, chans).write(str(path))
    return path


def _warp(src, dst):
    return subprocess.run([sys.executable, "-m", "lenslab", "warp", str(src), "-o", str(dst),
                           "--to", "perspective:fov=60", "--size", "16x16"], capture_output=True, text=True)


@pytest.mark.parametrize("ext", ["exr", "png"])
def test_warp_names_the_channels_it_leaves_out(layered, tmp_path, ext):
    out = tmp_path / f"view.{ext}"
    run = _warp(layered, out)
    assert run.returncode == 0, run.stderr
    others = [n for n in _names(layered) if n not in ("R", "G", "B", "A")]
    assert sorted(others) == ["N.x", "N.y", "N.z", "Z"]
    notes = [line for line in run.stderr.splitlines() if "not written" in line]
    assert len(notes) == 1, run.stderr  # one line, every channel in it
    for name in others:
        assert f"'{name}'" in notes[0]
    assert "warp resamples colour and alpha only" in notes[0]
    assert _names(out) == ["R", "G", "B", "A"]


def test_no_note_without_other_channels(layered, tmp_path):
    plain = tmp_path / "plain.exr"
    chans = {c: np.full((16, 32), 0.5, np.float32) for c in "RGB"}
    OpenEXR.File({"type": OpenEXR.scanlineimage, "compression": OpenEXR.ZIP_COMPRESSION}, chans).write(str(plain))
    run = _warp(plain, tmp_path / "view.exr")
    assert run.returncode == 0, run.stderr
    assert "not written" not in run.stderr
