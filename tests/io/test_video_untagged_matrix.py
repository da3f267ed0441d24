"""A clip whose Y'CbCr matrix is not tagged (what ``ffmpeg -i frame.png -pix_fmt yuv420p clip.mp4`` makes) is decoded
with the matrix FFmpeg coded and decodes it with, BT.601 (swscale's default, ``SWS_CS_DEFAULT``), not BT.709: the
frames lenslab reads are the frames ``ffmpeg -i clip -pix_fmt rgb24`` gives (they were 8.7 codes off on average, 39
at the 99th percentile, on FFmpeg's test pattern), and a clip lenslab writes back untagged is read by FFmpeg as it
was read."""

from __future__ import annotations

import json
import shutil
import subprocess

import numpy as np
import pytest

pytestmark = pytest.mark.skipif(shutil.which("ffmpeg") is None or shutil.which("ffprobe") is None,
                                reason="needs Debian's ffmpeg (installed in CI)")


def ffmpeg(*args) -> None:
    subprocess.run(["ffmpeg", "-v", "error", "-y", *map(str, args)], check=True)


def untagged_clip(path, size="128x64") -> None:
    """FFmpeg's saturated test pattern converted from RGB to 4:4:4 Y'CbCr by FFmpeg with no colour tags given."""
    ffmpeg("-f", "lavfi", "-i", f"testsrc2=size={size}:rate=1", "-frames:v", "1", "-pix_fmt", "yuv444p",
           "-c:v", "ffv1", path)
    shown = subprocess.run(["ffprobe", "-v", "error", "-show_entries", "stream=color_space", "-of", "json", str(path)],
                           capture_output=True, text=True, check=True).stdout
    assert json.loads(shown)["streams"][0].get("color_space", "unknown") == "unknown"  # the premise: no matrix tag


def ffmpeg_rgb(path, out) -> np.ndarray:
    """FFmpeg's own decode of the clip's first frame to 8-bit R'G'B' (H x W x 3, float64 codes)."""
    import cv2

    ffmpeg("-i", path, "-frames:v", "1", "-pix_fmt", "rgb24", out)
    return cv2.imread(str(out), cv2.IMREAD_COLOR)[..., ::-1].astype(np.float64)


def lenslab_codes(path) -> np.ndarray:
    """lenslab's first frame of the clip as 8-bit codes of the BT.1886 curve it decoded (gamma 2.4, black 0)."""
    from lenslab.io.video.clips import read_frames

    _, linear = next(iter(read_frames(path, 0, 1)))
    return np.clip(linear.astype(np.float64), 0.0, 1.0) ** (1 / 2.4) * 255.0


def test_an_untagged_clip_reads_as_ffmpeg_decodes_it(tmp_path):
    untagged_clip(tmp_path / "c.mkv")
    ref = ffmpeg_rgb(tmp_path / "c.mkv", tmp_path / "ref.png")
    diff = np.abs(lenslab_codes(tmp_path / "c.mkv") - ref)
    # FFmpeg rounds its 8-bit output (0.5 code) after a fixed-point matrix of its own (about 1 code more)
    assert diff.mean() < 0.5 and np.percentile(diff, 99) <= 1.5, (diff.mean(), np.percentile(diff, 99))


def test_an_untagged_clip_written_back_reads_in_ffmpeg_as_it_was(tmp_path):
    """Warped onto itself and written with its own (absent) tags, the clip is the one FFmpeg read before."""
    untagged_clip(tmp_path / "c.mkv")
    from lenslab.cli.main import main

    assert main(["warp", str(tmp_path / "c.mkv"), "-o", str(tmp_path / "w.mkv"), "--to", "equirect", "--from",
                 "equirect", "--size", "128x64", "--codec", "ffv1", "-q"]) == 0
    before = ffmpeg_rgb(tmp_path / "c.mkv", tmp_path / "before.png")
    after = ffmpeg_rgb(tmp_path / "w.mkv", tmp_path / "after.png")
    diff = np.abs(after - before)
    # the identity warp reads every pixel at its own centre; FFV1 10-bit 4:4:4 adds no loss: FFmpeg's rounding twice
    assert diff.mean() < 0.5 and np.percentile(diff, 99) <= 2.0, (diff.mean(), np.percentile(diff, 99))
