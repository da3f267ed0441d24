"""Frames smaller than x265 takes (16 x 16) that come with their input, not a --size (convert's image sequence, a
warp of a small clip at its default size), are refused in one line (exit 1) that says what to give instead: another
codec, which then writes the clip (FFmpeg, through PyAV, decodes it at the frames' size), or larger frames (a warp's
--size)."""

from __future__ import annotations

import pytest

av = pytest.importorskip("av")

from tests.io.test_video_encoder_open import encoder_opens  # noqa: E402
from tests.io.test_video_x265_small_frames import _decoded, _lenslab, _noise  # noqa: E402


@pytest.fixture(scope="module", autouse=True)
def _has_x265():
    if "libx265" not in av.codecs_available:
        pytest.skip("this FFmpeg has no libx265")


def test_small_frames_to_h265_are_told_the_way_out(tmp_path):
    w, h = 8, 8
    assert not encoder_opens("libx265", "yuv420p10le", w, h, str(tmp_path / "probe.mp4"))
    (tmp_path / "probe.mp4").unlink(missing_ok=True)
    frames = _noise(tmp_path / "frames", w, h, 2)
    run = _lenslab("convert", frames, "--to", "mp4", "-o", tmp_path / "c.mp4", "--codec", "h265")
    [line] = run.stderr.strip().splitlines()
    assert run.returncode == 1 and line.endswith("give frames of 16 x 16 or larger, or --codec h264")
    again = _lenslab("convert", frames, "--to", "mp4", "-o", tmp_path / "c.mp4", "--codec", "h264", "-q")
    assert again.returncode == 0, again.stderr
    assert _decoded(tmp_path / "c.mp4") == (w, h, 2, "h264")


def test_a_small_clip_warped_at_its_default_size_is_told_the_way_out(tmp_path):
    clip = tmp_path / "small.mkv"
    assert _lenslab("convert", _noise(tmp_path / "frames", 12, 6, 2), "--to", "mkv", "-o", clip, "-q").returncode == 0
    run = _lenslab("warp", clip, "-o", tmp_path / "w.mp4", "--to", "equirect", "--codec", "h265")
    [line] = run.stderr.strip().splitlines()
    assert run.returncode == 1 and "give --size 16x16 or larger, or --codec h264" in line, line
    again = _lenslab("warp", clip, "-o", tmp_path / "w.mp4", "--to", "equirect", "--codec", "h265", "--size", "16x16",
                     "-q")
    assert again.returncode == 0, again.stderr
    assert _decoded(tmp_path / "w.mp4")[:2] == (16, 16)
