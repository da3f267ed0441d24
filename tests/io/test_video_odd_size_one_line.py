"""A warp to an H.264 or H.265 clip of an odd --size is a usage error (exit 2) in one line, before any frame: x265 refuses 4:2:0 frames of
an odd width or height (checked on PyAV directly first: FFmpeg's own refusal), and it used to print its own two
``x265 [error]`` lines on standard error before lenslab's. Run as a command, since x265 writes to the process's
standard error itself."""

from __future__ import annotations

import subprocess
import sys

import pytest

av = pytest.importorskip("av")

from tests.io.test_video_encoder_open import encoder_opens  # noqa: E402
from tests.warp.test_video_warp_imports import _clip  # noqa: E402  (a 3-frame H.264 clip, by PyAV)


def _x265_opens(width: int, height: int, tmp_path) -> bool:
    """Whether FFmpeg's libx265 (through PyAV, no lenslab) opens for yuv420p10le frames of this size."""
    if "libx265" not in av.codecs_available:
        pytest.skip("this FFmpeg has no libx265")
    return encoder_opens("libx265", "yuv420p10le", width, height, str(tmp_path / "probe.mp4"))


@pytest.mark.parametrize("codec, size", [("h265", "63x63"), ("h265", "64x63"), ("h264", "63x64")])
def test_an_odd_size_is_one_error_line(tmp_path, codec, size):
    assert _x265_opens(64, 64, tmp_path) and not _x265_opens(63, 63, tmp_path)
    (tmp_path / "probe.mp4").unlink(missing_ok=True)
    clip = tmp_path / "clip.mp4"
    _clip(clip)
    run = subprocess.run([sys.executable, "-m", "lenslab", "warp", str(clip), "-o", str(tmp_path / "fish.mp4"),
                          "--from", "equirect", "--to", "fisheye:fov=180", "--size", size, "--codec", codec],
                         capture_output=True, text=True)
    # the size is on the command line: a usage error (exit 2), before any frame is decoded
    assert run.returncode == 2
    w, h = (int(v) for v in size.split("x"))
    encoder = {"h264": "libx264", "h265": "libx265"}[codec]
    assert run.stderr.strip().splitlines() == [
        f"lenslab warp: error: --size {size}: the {encoder} encoder of this clip writes 4:2:0 "
        f"({'yuv420p10le' if codec == 'h265' else 'yuv420p'}), whose chroma needs an even width and height; "
        f"give --size {w + w % 2}x{h + h % 2}, or --codec ffv1 (4:4:4)"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["clip.mp4"]  # no output, no temporary


@pytest.mark.parametrize("codec", ["h264", "h265"])
def test_frames_of_an_odd_size_to_a_clip_are_one_error_line(tmp_path, codec):
    """`lenslab convert 'frames/*.exr' --to mp4` of 33 x 31 frames: one line naming the first frame and the
    encoder's need (it was PyAV's 'avcodec_open2("libx264", {})' error, and x265's own lines before it)."""
    import numpy as np

    import lenslab

    assert not encoder_opens("libx264", "yuv420p", 33, 31, str(tmp_path / "probe.mp4"))
    (tmp_path / "probe.mp4").unlink(missing_ok=True)
    frames = tmp_path / "frames"
    frames.mkdir()
    for i in range(3):
        lenslab.write(frames / f"f{i}.exr", np.full((31, 33, 3), 0.2 * i, np.float32))
    out = tmp_path / "clip.mp4"
    run = subprocess.run([sys.executable, "-m", "lenslab", "convert", str(frames / "*.exr"), "--to", "mp4",
                          "-o", str(out), "--codec", codec], capture_output=True, text=True)
    assert run.returncode == 1
    encoder, pix = {"h264": ("libx264", "yuv420p"), "h265": ("libx265", "yuv420p10le")}[codec]
    assert run.stderr.strip().splitlines() == [
        f"lenslab convert: error: {frames / 'f0.exr'}: the {encoder} encoder cannot encode 33 x 31 frames in {pix}: "
        "its 4:2:0 chroma needs an even width and height; --codec ffv1 (4:4:4) encodes them"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["frames"]  # no clip, no temporary


def test_an_odd_size_to_the_default_codec_is_a_usage_error_before_any_frame(tmp_path, monkeypatch, capsys):
    """`lenslab warp pano.mp4 -o f.mp4 --size 513x513`: .mp4's default encoder, x264, refuses 513 x 513 in 4:2:0
    and opens for the even size suggested (FFmpeg's answers, through PyAV); lenslab says so with exit 2 before it
    probes or decodes the clip."""
    from lenslab.cli.main import main

    assert not encoder_opens("libx264", "yuv420p", 513, 513, str(tmp_path / "probe.mp4"))
    assert encoder_opens("libx264", "yuv420p", 514, 514, str(tmp_path / "probe.mp4"))
    (tmp_path / "probe.mp4").unlink(missing_ok=True)
    from tests.io.test_video_x265_min_size import unopened_clip

    clip = unopened_clip(tmp_path / "pano.mp4", monkeypatch)
    assert main(["warp", str(clip), "-o", str(tmp_path / "f.mp4"), "--to", "fisheye:fov=180",
                 "--size", "513x513"]) == 2
    err = capsys.readouterr().err
    assert "--size 513x513" in err and "--size 514x514" in err and "the clip was opened" not in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pano.mp4"]
