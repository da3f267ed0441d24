"""A warped clip's encoder opens right after its writer is made, before the first frame: its set-up overlaps the
warp's map, and a frame size the encoder refuses is one error line before any frame is decoded or warped, with no
file left behind.

The refusal is FFmpeg's own: libx264 does not open on 4:2:0 frames of an odd width or height (checked on PyAV
directly first), and neither does the clip's writer."""

from __future__ import annotations

from fractions import Fraction

import pytest

av = pytest.importorskip("av")

from lenslab.cli.main import main  # noqa: E402
from lenslab.errors import FormatError  # noqa: E402
from lenslab.io.video import VideoInfo, VideoWriter  # noqa: E402
from lenslab.io.video.codecs import open_encoder  # noqa: E402
from tests.warp.test_video_warp_imports import _clip  # noqa: E402  (a 3-frame H.264 clip, by PyAV)


def _x264_opens(width: int, height: int) -> bool:
    """Whether FFmpeg's libx264 (through PyAV, no lenslab) opens for yuv420p frames of this size."""
    return encoder_opens("libx264", "yuv420p", width, height)


def encoder_opens(encoder: str, pix_fmt: str, width: int, height: int, where: str = "unused.mp4") -> bool:
    """Whether FFmpeg's ``encoder`` (through PyAV, no lenslab) opens for ``pix_fmt`` frames of this size."""
    with av.open(where, "w", format="mp4") as c:
        s = c.add_stream(encoder, rate=Fraction(24))
        s.width, s.height, s.pix_fmt = width, height, pix_fmt
        try:
            s.codec_context.open()
        except av.error.FFmpegError:
            return False
        return True


def test_an_encoder_opened_first_writes_the_same_clip(tmp_path):
    """x264 opened before the first frame (with frame threads) writes the same bytes as x264 opened by it."""
    import numpy as np

    info = VideoInfo(64, 32, Fraction(24), 3, "h264", "yuv420p")
    frames = [np.full((32, 32, 3), 0.1 * (i + 1), np.float32) for i in range(6)]
    for name, first in (("lazy.mp4", False), ("first.mp4", True)):
        writer = VideoWriter(tmp_path / name, info, size=(32, 32))
        if first:
            open_encoder(writer.container, writer.stream)
            assert writer.stream.codec_context.is_open and writer.count == 0
        with writer:
            for f in frames:
                writer.write(f)
    assert (tmp_path / "first.mp4").read_bytes() == (tmp_path / "lazy.mp4").read_bytes()


def test_an_odd_size_is_refused_before_the_first_frame(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert _x264_opens(64, 64) and not _x264_opens(63, 63) and not _x264_opens(64, 63)
    info = VideoInfo(64, 32, Fraction(24), 3, "h264", "yuv420p")
    writer = VideoWriter(tmp_path / "out.mp4", info, size=(63, 64))
    with pytest.raises(FormatError, match=r"libx264 encoder cannot encode 63 x 64 frames in yuv420p: its 4:2:0 chroma "
                                          r"needs an even width and height"):
        open_encoder(writer.container, writer.stream)
    assert not (tmp_path / "out.mp4").exists()


def test_warp_to_an_odd_size_is_one_error_line_and_no_file(tmp_path, capsys):
    clip = tmp_path / "clip.mp4"
    _clip(clip)
    out = tmp_path / "fish.mp4"
    assert main(["warp", str(clip), "-o", str(out), "--to", "fisheye:fov=180", "--from", "equirect",
                 "--size", "63x63", "-q"]) == 2  # the size is on the command line: a usage error
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--size 63x63" in err[0] and "even width and height" in err[0], err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["clip.mp4"]  # no output, no temporary
