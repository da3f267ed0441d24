"""A clip warped into image files (``-o frames/%04d.exr``) draws each frame's colour and alpha into the one RGBA image
written, as a batch of still images does: its peak is that of a batch of two stills of the clip's size warped into
the same output (both keep their maps for the next image), not that and another copy of the output.

Measured as :mod:`tests.jobs.test_warp_enlarging_memory` does: each command in a child process under the address-space
limit of :mod:`tests.hostile_run`, its peak resident memory (the kernel's ``getrusage``) beyond that of the same command
into 64 x 32. Before (main, load 5 on 2 cores): the clip's two frames into 4096 x 2048 EXR 398 MB beyond, the two stills
265 MB (colour and alpha were joined in a new image, 134 MB); now 267 and 264 MB. No time is measured.
"""

from __future__ import annotations

import sys

import numpy as np
import pytest

import lenslab.io as lio
from tests.hostile_run import run

av = pytest.importorskip("av")

from tests.warp.test_video_warp_imports import _clip  # noqa: E402  (an H.264 clip, by PyAV)

LENSLAB = [sys.executable, "-m", "lenslab"]
W, H = 4096, 2048
#: a batch's maps and a decoder's frames differ by a few MB; a copy of the output would be 134 MB
SLACK_MB = 25.0


def test_frames_written_as_images_peak_as_a_batch_of_stills(tmp_path):
    clip = tmp_path / "clip.mp4"
    _clip(clip, 512, 256, 2)
    for name in ("a", "b"):
        lio.write(tmp_path / f"{name}.png", np.full((256, 512, 3), 0.5, np.float32))
    beyond = {}
    for kind in ("clip", "stills"):
        peaks = {}
        for size in ("64x32", f"{W}x{H}"):
            out = tmp_path / f"{kind}-{size}"
            argv = [str(clip), "-o", str(out / "%04d.exr")] if kind == "clip" else \
                [str(tmp_path / "a.png"), str(tmp_path / "b.png"), "-o", str(out), "--format", "exr"]
            done = run(LENSLAB + ["warp", *argv, "--to", "equirect", "--size", size, "-q"])
            assert done.returncode == 0, done.stderr
            peaks[size] = done.peak_mb
        beyond[kind] = peaks[f"{W}x{H}"] - peaks["64x32"]
    assert beyond["clip"] <= beyond["stills"] + SLACK_MB, beyond
    import OpenImageIO as oiio

    frames = sorted((tmp_path / f"clip-{W}x{H}").glob("*.exr"))
    assert [f.name for f in frames] == ["0000.exr", "0001.exr"]
    spec = oiio.ImageInput.open(str(frames[-1])).spec()
    assert (spec.width, spec.height, list(spec.channelnames)) == (W, H, ["R", "G", "B", "A"])
