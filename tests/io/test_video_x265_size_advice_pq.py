"""``--codec h265 --size WxH`` below x265's smallest frame is refused before the clip is probed, so the line cannot know
whether the clip is SDR or PQ/HLG: its advice must fit both. For a PQ clip (PyAV reads its transfer as SMPTE ST 2084)
the line names a larger --size that FFmpeg's libx265 itself opens, and offers H.264 only for an SDR clip."""

from __future__ import annotations

import pytest

av = pytest.importorskip("av")

from tests.io.test_video_encoder_open import encoder_opens  # noqa: E402
from tests.io.test_video_x265_small_frames import _lenslab, _noise  # noqa: E402

#: H.273 TransferCharacteristics 16: SMPTE ST 2084 (PQ), as FFmpeg's AVColorTransferCharacteristic numbers it
PQ_TRC = 16


@pytest.fixture(scope="module", autouse=True)
def _has_x265():
    if "libx265" not in av.codecs_available:
        pytest.skip("this FFmpeg has no libx265")


def _transfer(path) -> int:
    with av.open(str(path)) as c:
        return int(c.streams.video[0].codec_context.color_trc)


def test_the_size_advice_before_the_probe_fits_a_pq_clip(tmp_path):
    clip = tmp_path / "pq.mov"
    made = _lenslab("convert", _noise(tmp_path / "frames", 32, 16, 2), "--to", "mov", "--transfer", "pq", "-o", clip,
                    "-q")
    assert made.returncode == 0, made.stderr
    assert _transfer(clip) == PQ_TRC  # the clip is PQ, by FFmpeg's reading of its stream
    assert not encoder_opens("libx265", "yuv420p10le", 8, 8, str(tmp_path / "probe.mp4"))  # a size x265 refuses
    assert encoder_opens("libx265", "yuv420p10le", 16, 16, str(tmp_path / "probe2.mp4"))  # and the one named
    run = _lenslab("warp", clip, "-o", tmp_path / "w.mp4", "--to", "fisheye:fov=180", "--codec", "h265", "--size",
                   "8x8")
    [line] = run.stderr.strip().splitlines()
    assert run.returncode == 2, run.stderr
    assert line.endswith("give --size 16x16 or larger, or --codec h264 for an SDR clip"), line
    assert not (tmp_path / "w.mp4").exists()
