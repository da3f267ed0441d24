"""``lenslab bench batch`` times like against like: its ffmpeg command and its lenslab command, run on
the same EXR frame, make the same 180-degree fisheye (ffmpeg's v360 output is the external value).

ffmpeg is part of CI (``.ci/run`` installs it), so it is required here, not skipped.
"""

from __future__ import annotations

import json
import math
import subprocess

import numpy as np

from lenslab.bench.batch import _ffmpeg_cmd, _lenslab_cmd
from lenslab.cli.main import main
from lenslab.io import read, write

W, H, SIDE = 512, 256, 128
AMP = 0.3

#: the frame's slope is at most AMP * (2 pi / W + pi / H) = 0.0074 per source pixel; v360 stretches
#: its [-1, 1] range between the first and last pixel centres, lenslab reads pixel centres, so the
#: two sample positions differ by at most half a pixel: <= 0.0037. Both outputs are half floats
#: (relative 2^-11 of values <= 0.8: <= 4e-4 each), and ffmpeg 5.1's v360 works on 16-bit integers
#: (1.5e-5). 0.0037 + 2 * 4e-4 + 1.5e-5 = 0.0045, rounded up
TOL = 0.005


def _frame() -> np.ndarray:
    """A smooth frame inside [0.2, 0.8] (v360 in ffmpeg 5.1 converts float frames to 16-bit integers,
    which clips values above 1), a different pattern per channel."""
    y, x = np.mgrid[0:H, 0:W].astype(np.float64) + 0.5
    lon, lat = 2 * np.pi * x / W, np.pi * y / H
    chans = [0.5 + AMP * np.sin(lon) * np.cos(lat), 0.5 + AMP * np.cos(lon) * np.sin(lat),
             0.5 + AMP * np.sin(lon + lat)]
    return np.stack(chans, axis=-1).astype(np.float32)


def test_batch_commands_make_the_same_fisheye(tmp_path):
    src = tmp_path / "in"
    src.mkdir()
    write(src / "frame0000.exr", _frame())
    (tmp_path / "ffmpeg").mkdir()
    subprocess.run(_ffmpeg_cmd(src, tmp_path / "ffmpeg", SIDE, True), check=True)
    subprocess.run(_lenslab_cmd(src, tmp_path / "lenslab", SIDE), check=True)
    theirs = read(tmp_path / "ffmpeg" / "frame0001.exr")[0][..., :3]  # ffmpeg numbers frames from 1
    ours = read(tmp_path / "lenslab" / "frame0000.exr")[0]
    assert theirs.shape == (SIDE, SIDE, 3) and ours.shape == (SIDE, SIDE, 4)
    # inside 0.9 of the image circle (elevations under 81 degrees): away from the poles, where v360
    # clamps rows and lenslab reads across, and from the rim, where lenslab's coverage falls below 1
    y, x = np.mgrid[0:SIDE, 0:SIDE] + 0.5
    inner = np.hypot(x - SIDE / 2, y - SIDE / 2) < 0.9 * SIDE / 2
    assert inner.sum() > 0.6 * math.pi / 4 * SIDE * SIDE
    assert np.all(ours[..., 3][inner] == 1)
    np.testing.assert_allclose(ours[..., :3][inner], theirs[inner], rtol=0, atol=TOL)


def test_bench_batch_writes_its_aims(tmp_path):
    out = tmp_path / "batch.json"
    assert main(["bench", "batch", "--frames", "1", "--size", "128x64", "--out-size", "32", "--repeat", "1",
                 "--json", str(out)]) == 0
    figures = {f["key"]: f for f in json.loads(out.read_text())["figures"]}
    assert figures["batch.one_thread_wall"]["aim"] == 0.7  # the aim: at most 0.7x v360 with one thread each
    assert figures["batch.all_threads_wall"]["aim"] == 1.0  # and ahead of it with every thread
    assert all(f["value"] > 0 for f in figures.values())
