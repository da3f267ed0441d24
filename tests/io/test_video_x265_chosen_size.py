"""H.265 that lenslab picks by itself (a PQ or HLG clip warped to ``.mp4``, an image sequence converted to an
H.265 clip) refuses frames under 16 x 16 in one line before the output or its temporary is made and before any frame
is decoded or encoded. It used to be found when the encoder opened: after the temporary was made, with a remedy
(``--codec h264``) that cannot hold a PQ clip.

The outside values: FFmpeg's libx265 itself, opened through PyAV (no lenslab), refuses 14 x 14 and opens 16 x 16
(``encoder_opens``); the PQ clip is written by PyAV with the transfer tag SMPTE ST 2084 (16) and read back by PyAV.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

av = pytest.importorskip("av")

from tests.io.test_video_encoder_open import encoder_opens  # noqa: E402

PQ = 16  # ITU-T H.273 TransferCharacteristics: SMPTE ST 2084


@pytest.fixture(autouse=True)
def x265_limits(tmp_path_factory):
    """libx265's own answer, through PyAV: 14 x 14 refused, 16 x 16 opened."""
    if "libx265" not in av.codecs_available:
        pytest.skip("this FFmpeg has no libx265")
    where = str(tmp_path_factory.mktemp("probe") / "probe.mp4")
    assert not encoder_opens("libx265", "yuv420p10le", 14, 14, where)
    assert encoder_opens("libx265", "yuv420p10le", 16, 16, where)


def pq_clip(path, w=32, h=32, frames=3):
    """A 10-bit H.265 clip tagged PQ / BT.2020, encoded by PyAV."""
    with av.open(str(path), "w") as c:
        s = c.add_stream("libx265", rate=Fraction(24))
        s.width, s.height, s.pix_fmt = w, h, "yuv420p10le"
        cc = s.codec_context
        cc.color_primaries, cc.color_trc, cc.colorspace, cc.color_range = 9, PQ, 9, 1
        cc.options = {"x265-params": "log-level=error"}
        for i in range(frames):
            f = av.VideoFrame.from_ndarray(np.full((h, w, 3), 100 + 40 * i, np.uint8), format="rgb24")
            f.pts = i
            c.mux(s.encode(f.reformat(format="yuv420p10le")))  # (a list of packets: each muxed)
        c.mux(s.encode())  # the frames the encoder still holds
    with av.open(str(path)) as c:
        assert int(c.streams.video[0].codec_context.color_trc) == PQ
    return path


def untouched(monkeypatch):
    """The decoder (``read_frames``) and the output's temporary (``atomic_write_path``) fail the test if used."""
    import lenslab.atomic as atomic
    import lenslab.io.video as video

    def fail(*args, **kwargs):
        raise AssertionError("used before the refusal")

    monkeypatch.setattr(video, "read_frames", fail)
    monkeypatch.setattr(atomic, "atomic_write_path", fail)


def test_a_pq_clip_warped_to_mp4_below_16_is_refused_before_any_frame_or_file(tmp_path, monkeypatch, capsys):
    from lenslab.cli.main import main

    clip = pq_clip(tmp_path / "pq.mp4")
    untouched(monkeypatch)
    capsys.readouterr()
    assert main(["warp", str(clip), "-o", str(tmp_path / "out.mp4"), "--from", "equirect", "--to",
                 "fisheye:fov=180", "--size", "14x14"]) == 1
    assert capsys.readouterr().err == (
        f"lenslab warp: error: {clip}: the libx265 encoder (H.265, .mp4's codec for a PQ clip) encodes frames of at "
        "least 16 x 16, not 14 x 14: give --size 16x16 or larger, or -o NAME.mov (ProRes) or NAME.mkv (FFV1), which "
        "keep its 10 bits\n")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pq.mp4"]  # no output, no temporary


def test_a_pq_clip_warped_to_mp4_at_16_is_h265(tmp_path):
    from lenslab.cli.main import main

    clip = pq_clip(tmp_path / "pq.mp4")
    out = tmp_path / "out.mp4"
    assert main(["warp", str(clip), "-o", str(out), "--from", "equirect", "--to", "fisheye:fov=180", "--size",
                 "16x16", "-q"]) == 0
    with av.open(str(out)) as c:
        cc = c.streams.video[0].codec_context
        assert (cc.name, cc.width, cc.height, int(cc.color_trc)) == ("hevc", 16, 16, PQ)


@pytest.mark.parametrize("options,chosen,other", [
    (["--codec", "h265"], "--codec h265", "--codec h264"),
    (["--transfer", "pq"], "H.265, .mp4's codec for a PQ clip",
     "-o NAME.mov (ProRes) or NAME.mkv (FFV1), which keep its 10 bits"),
    (["--transfer", "hlg"], "H.265, .mp4's codec for an HLG clip",
     "-o NAME.mov (ProRes) or NAME.mkv (FFV1), which keep its 10 bits"),
])
def test_frames_below_16_converted_to_h265_are_refused_before_any_is_encoded(tmp_path, monkeypatch, capsys, options,
                                                                             chosen, other):
    from lenslab.cli.main import main
    from lenslab.io import write

    frames = [tmp_path / f"f{i}.exr" for i in range(3)]
    for i, f in enumerate(frames):
        write(f, np.full((14, 14, 3), 0.25 * (i + 1), np.float32))
    import lenslab.io.video.clips as clips

    def no_encoding(*args, **kwargs):
        raise AssertionError("a frame was encoded")

    monkeypatch.setattr(clips.VideoWriter, "write", no_encoding)
    capsys.readouterr()
    assert main(["convert", *map(str, frames), "-o", str(tmp_path / "clip.mp4"), *options]) == 1
    assert capsys.readouterr().err == (
        f"lenslab convert: error: {frames[0]}: the libx265 encoder ({chosen}) encodes frames of at least 16 x 16, not "
        f"14 x 14: give frames of 16 x 16 or larger, or {other}\n")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["f0.exr", "f1.exr", "f2.exr"]  # no clip, no temporary


def test_a_pq_clip_shown_on_an_sdr_display_is_h264_at_14(tmp_path):
    """--display sRGB: the clip written holds the display's codes and tags, SDR, so .mp4 picks H.264, which encodes
    14 x 14 (PyAV reads it back so); the codec is chosen for the transfer written, not the one read."""
    pytest.importorskip("PyOpenColorIO")
    from lenslab.cli.main import main

    clip = pq_clip(tmp_path / "pq.mp4")
    out = tmp_path / "out.mp4"
    assert main(["warp", str(clip), "-o", str(out), "--from", "equirect", "--to", "fisheye:fov=180", "--size",
                 "14x14", "--display", "sRGB - Display", "-q"]) == 0
    with av.open(str(out)) as c:
        cc = c.streams.video[0].codec_context
        assert (cc.name, cc.width, cc.height) == ("h264", 14, 14) and int(cc.color_trc) != PQ


def test_an_sdr_clip_shown_on_a_pq_display_below_16_is_refused_before_any_frame(tmp_path, monkeypatch, capsys):
    pytest.importorskip("PyOpenColorIO")
    from lenslab.cli.main import main
    from tests.warp.test_video_warp_imports import _clip

    clip = tmp_path / "sdr.mp4"
    _clip(clip, 32, 32)
    untouched(monkeypatch)
    capsys.readouterr()
    assert main(["warp", str(clip), "-o", str(tmp_path / "out.mp4"), "--from", "equirect", "--to", "fisheye:fov=180",
                 "--size", "14x14", "--display", "Rec.2100-PQ - Display", "--view",
                 "ACES 2.0 - HDR 1000 nits (Rec.2020)"]) == 1
    assert capsys.readouterr().err.startswith(
        f"lenslab warp: error: {clip}: the libx265 encoder (H.265, .mp4's codec for a PQ clip) encodes frames of at "
        "least 16 x 16, not 14 x 14: give --size 16x16 or larger")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["sdr.mp4"]
