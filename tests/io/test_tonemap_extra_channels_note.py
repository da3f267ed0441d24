"""`lenslab tonemap` of an EXR with channels besides colour and alpha (depth ``Z``, normals ``N.x``...)
writes colour only, as `lenslab convert --to png` and `lenslab warp` do, and says so in one note line
naming each channel left out (it said nothing before). Expected values: OpenImageIO's channel names of
the source and of the output."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

OpenEXR = pytest.importorskip("OpenEXR")
from tests.io.test_warp_extra_channels_note import _names  # noqa: E402  (OpenImageIO's channel names)


def _exr(path, extra: bool):
    rng = np.random.default_rng(5)
    h, w = 12, 20
    chans = {c: rng.uniform(0, 4, (h, w)).astype(np.float32) for c in "RGB"}
    if extra:
        chans["Z"] = rng.uniform(1, 1e3, (h, w)).astype(np.float32)
        for c in ("N.x", "N.y", "N.z"):
            chans[c] = rng.uniform(-1, 1, (h, w)).astype(np.float16)
    OpenEXR.File({"type": OpenEXR.scanlineimage, "compression": OpenEXR.ZIP_COMPRESSION}, chans).write(str(path))
    return path


def _tonemap(*args):
    return subprocess.run([sys.executable, "-m", "lenslab", "tonemap", *map(str, args)],
                          capture_output=True, text=True)


@pytest.mark.parametrize("ext", ["png", "exr"])
def test_tonemap_names_the_channels_it_leaves_out(tmp_path, ext):
    src = _exr(tmp_path / "render.exr", extra=True)
    out = tmp_path / f"t.{ext}"
    run = _tonemap(src, "-o", out)
    assert run.returncode == 0, run.stderr
    others = [n for n in _names(src) if n not in ("R", "G", "B")]
    assert sorted(others) == ["N.x", "N.y", "N.z", "Z"]
    notes = [line for line in run.stderr.splitlines() if "not written" in line]
    assert len(notes) == 1, run.stderr  # one line, every channel in it
    assert notes[0].startswith(f"lenslab tonemap: note: {src}: channel(s) ")
    for name in others:
        assert f"'{name}'" in notes[0]
    assert sorted(_names(out)) == ["B", "G", "R"]


def test_a_batch_says_it_per_file_and_a_plain_file_says_nothing(tmp_path):
    layered = _exr(tmp_path / "a.exr", extra=True)
    plain = _exr(tmp_path / "b.exr", extra=False)
    run = _tonemap(layered, plain, "-o", tmp_path / "out", "--format", "png")
    assert run.returncode == 0, run.stderr
    notes = [line for line in run.stderr.splitlines() if "not written" in line]
    assert len(notes) == 1 and str(layered) in notes[0], run.stderr
    assert _tonemap(plain, "-o", tmp_path / "p.png").stderr.count("not written") == 0
