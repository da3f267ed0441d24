"""A clip converted to H.265 (``--codec h265``, or .mp4's codec for a PQ clip) whose frames are smaller than x265
takes (16 x 16) is refused in one line (exit 1) that gives what fits a clip: convert keeps a clip's size, so the way
out is another codec or ``lenslab warp --to SPEC --size``, not "frames of 16 x 16 or larger". Outside values: the
codec, size and frame count FFmpeg (through PyAV) decodes from the clips the advice writes."""

from __future__ import annotations

import pytest

av = pytest.importorskip("av")

from tests.io.test_video_x265_small_frames import _decoded, _lenslab, _noise  # noqa: E402


@pytest.fixture(scope="module", autouse=True)
def _has_x265():
    if "libx265" not in av.codecs_available:
        pytest.skip("this FFmpeg has no libx265")


@pytest.fixture
def small_clip(tmp_path):
    clip = tmp_path / "small.mkv"
    assert _lenslab("convert", _noise(tmp_path / "frames", 12, 6, 2), "--to", "mkv", "-o", clip, "-q").returncode == 0
    return clip


def _refused(clip, out, *options) -> str:
    """The one line of a refused convert of ``clip`` to ``out`` (exit 1, no output made)."""
    run = _lenslab("convert", clip, "-o", out, *options)
    [line] = run.stderr.strip().splitlines()
    assert run.returncode == 1 and not out.exists() and "frames of 16 x 16 or larger" not in line, line
    return line


def test_a_small_clip_converted_to_h265_is_told_what_fits_a_clip(tmp_path, small_clip):
    line = _refused(small_clip, tmp_path / "c.mp4", "--codec", "h265")
    assert line.endswith("not 12 x 6: convert keeps a clip's size: give --codec h264, or enlarge it with lenslab warp "
                         "--to SPEC --size 16x16"), line
    assert _lenslab("convert", small_clip, "-o", tmp_path / "c.mp4", "--codec", "h264", "-q").returncode == 0
    assert _decoded(tmp_path / "c.mp4") == (12, 6, 2, "h264")
    warped = _lenslab("warp", small_clip, "-o", tmp_path / "w.mp4", "--to", "equirect", "--size", "16x16", "--codec",
                      "h265", "-q")
    assert warped.returncode == 0, warped.stderr
    assert _decoded(tmp_path / "w.mp4") == (16, 16, 2, "hevc")


def test_a_small_clip_converted_to_pq_names_the_ten_bit_containers_and_warp(tmp_path, small_clip):
    line = _refused(small_clip, tmp_path / "c.mp4", "--transfer", "pq")
    assert line.endswith(
        "convert keeps a clip's size: give -o NAME.mov (ProRes) or NAME.mkv (FFV1), which keep its 10 bits, or enlarge "
        "it with lenslab warp --to SPEC --size 16x16"), line
