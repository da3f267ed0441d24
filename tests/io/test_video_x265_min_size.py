"""``lenslab warp clip.mp4 -o out.mp4 --codec h265 --size 8x8``: a size below x265's smallest frame is a usage error
(exit 2) in one line naming the smallest size to give, before the clip is probed or decoded. x265's limits come
from FFmpeg's libx265 itself, opened through PyAV for each even side (no lenslab code): the test finds the smallest
width and height it opens and checks that lenslab's line names exactly those."""

from __future__ import annotations

import pytest

av = pytest.importorskip("av")

from tests.io.test_video_encoder_open import encoder_opens  # noqa: E402
from tests.warp.test_video_warp_imports import _clip  # noqa: E402  (a 3-frame H.264 clip, by PyAV)


def _smallest_side(tmp_path, across: bool) -> int:
    """The smallest even side libx265 opens for (yuv420p10le, the other side 64), by trying each from 2 up."""
    if "libx265" not in av.codecs_available:
        pytest.skip("this FFmpeg has no libx265")
    where = str(tmp_path / "probe.mp4")
    try:
        for side in range(2, 66, 2):
            if encoder_opens("libx265", "yuv420p10le", *((side, 64) if across else (64, side)), where):
                return side
    finally:
        (tmp_path / "probe.mp4").unlink(missing_ok=True)
    raise AssertionError("libx265 opened for no side up to 64")


def unopened_clip(path, monkeypatch):
    """A 3-frame H.264 clip at ``path`` that the command must not open: lenslab's probe and decoder fail the test
    if called (a usage error comes before them)."""
    import lenslab.io.video as video

    _clip(path)

    def untouched(*args, **kwargs):
        raise AssertionError("the clip was opened")

    monkeypatch.setattr(video, "read_frames", untouched)
    monkeypatch.setattr(video, "probe_video", untouched)
    return path


@pytest.mark.parametrize("size", ["8x8", "64x8", "10x64", "9x9"])
def test_a_size_below_x265s_smallest_is_a_usage_error_before_any_frame(tmp_path, monkeypatch, capsys, size):
    from lenslab.cli.main import main

    min_w, min_h = _smallest_side(tmp_path, True), _smallest_side(tmp_path, False)
    w, h = (int(v) for v in size.split("x"))
    assert w < min_w or h < min_h  # a size FFmpeg's libx265 itself refuses
    want = (max(w + w % 2, min_w), max(h + h % 2, min_h))
    assert encoder_opens("libx265", "yuv420p10le", *want, str(tmp_path / "probe.mp4"))  # and the one named opens
    (tmp_path / "probe.mp4").unlink(missing_ok=True)
    clip = unopened_clip(tmp_path / "clip.mp4", monkeypatch)
    assert main(["warp", str(clip), "-o", str(tmp_path / "out.mp4"), "--from", "equirect", "--to", "fisheye:fov=180",
                 "--codec", "h265", "--size", size]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert lines == [f"lenslab warp: error: --size {size}: the libx265 encoder (--codec h265) encodes frames of at "
                     f"least {min_w} x {min_h}; give --size {want[0]}x{want[1]} or larger, or --codec h264 for an SDR clip"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["clip.mp4"]  # no output, no temporary


def test_the_smallest_size_x265_opens_is_warped(tmp_path):
    """At the smallest size libx265 opens, the warp to H.265 runs and writes the clip at that size (PyAV reads it)."""
    from lenslab.cli.main import main

    side = max(_smallest_side(tmp_path, True), _smallest_side(tmp_path, False))
    clip = tmp_path / "clip.mp4"
    _clip(clip)
    out = tmp_path / "out.mp4"
    assert main(["warp", str(clip), "-o", str(out), "--from", "equirect", "--to", "fisheye:fov=180", "--codec", "h265",
                 "--size", f"{side}x{side}"]) == 0
    with av.open(str(out)) as c:
        s = c.streams.video[0]
        assert (s.codec_context.name, s.codec_context.width, s.codec_context.height) == ("hevc", side, side)
