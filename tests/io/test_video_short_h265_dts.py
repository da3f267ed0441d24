"""A clip of one or two frames encoded as H.265 (a PQ clip's .mp4) is written whole, in a batch too: libx265 hands its
first packet back with an undefined decoding time (dts) when it flushes so few frames, which the MP4 muxer refuses
("pts/dts pair unsupported"); the second of three such clips warped in one run failed with FFmpeg's
"Not yet implemented in FFmpeg, patches welcome". Such a dts is set from the packet's own pts (no frame is reordered
in a clip this short), kept increasing.

Outside values: the clips are made by Debian's ffmpeg (H.265 10-bit, tagged PQ); each output is read back by PyAV
(FFmpeg): H.265, the source's frame count, every dts defined and no later than its pts."""

from __future__ import annotations

import shutil
import subprocess

import pytest

from lenslab.cli.main import main

av = pytest.importorskip("av")
FFMPEG = shutil.which("ffmpeg")
pytestmark = pytest.mark.skipif(FFMPEG is None, reason="needs the ffmpeg command (CI installs Debian's)")


@pytest.mark.parametrize("frames", [1, 2])
def test_short_pq_clips_are_written_whole(tmp_path, capsys, frames):
    clips = tmp_path / "clips"
    clips.mkdir()
    subprocess.run([FFMPEG, "-v", "error", "-y", "-f", "lavfi", "-i", "testsrc=size=64x32:rate=10", "-frames:v",
                    str(frames), "-c:v", "libx265", "-pix_fmt", "yuv420p10le", "-color_primaries", "bt2020",
                    "-color_trc", "smpte2084", "-colorspace", "bt2020nc", "-x265-params", "log-level=none",
                    str(clips / "c0.mp4")], check=True, timeout=120)
    for i in (1, 2):
        shutil.copy(clips / "c0.mp4", clips / f"c{i}.mp4")
    av.logging.set_level(av.logging.ERROR)  # (FFmpeg's own lines, as a user with logging on sees them)
    try:
        code = main(["warp", str(clips), "-o", str(tmp_path / "out"), "--from", "equirect", "--to", "equirect",
                     "--size", "32x16", "--jobs", "1", "-q"])
    finally:
        av.logging.set_level(None)
    assert code == 0, capsys.readouterr().err
    for i in range(3):
        with av.open(str(tmp_path / "out" / f"c{i}.mp4")) as c:
            assert c.streams.video[0].codec_context.name == "hevc"
            packets = [p for p in c.demux(video=0) if p.size]
        assert len(packets) == frames
        assert all(p.dts is not None and p.dts <= p.pts for p in packets)
