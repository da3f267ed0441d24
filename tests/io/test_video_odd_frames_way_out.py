"""Frames of an odd side that ``lenslab convert`` makes an .mp4 of (H.264's 4:2:0 chroma needs even sides) are refused
in one line that names the way out, ``--codec ffv1`` (4:4:4), as a warp's odd ``--size`` is: the line said only what the
encoder needs, and the frames bring their own size, which no option of convert changes.

Outside values: exit code 1 (a failed input, the brief's rule), and the clip the named way out writes as PyAV (FFmpeg)
decodes it: three 15 x 15 frames."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import write

av = pytest.importorskip("av")


def _frames(tmp_path):
    paths = []
    for i in range(3):
        paths.append(str(tmp_path / f"f{i}.exr"))
        write(paths[-1], np.full((15, 15, 3), 0.2 * (i + 1), np.float32), pixel_type="float")
    return paths


def test_odd_frames_name_the_codec_that_takes_them(tmp_path, capsys):
    frames = _frames(tmp_path)
    capsys.readouterr()
    assert main(["convert", *frames, "-o", str(tmp_path / "clip.mp4")]) == 1
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "even width and height" in err
    assert err.endswith("; --codec ffv1 (4:4:4) encodes them")
    assert not (tmp_path / "clip.mp4").exists()
    assert main(["convert", *frames, "-o", str(tmp_path / "clip.mkv"), "--codec", "ffv1", "-q"]) == 0
    with av.open(str(tmp_path / "clip.mkv")) as container:
        assert [(f.width, f.height) for f in container.decode(video=0)] == [(15, 15)] * 3
