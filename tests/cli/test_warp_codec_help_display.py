"""``lenslab warp --help`` says what picks an .mp4's codec: the transfer the clip is written with, not the input's (a
PQ clip shown on an sRGB display is H.264, an SDR clip shown on a PQ display H.265 10-bit). It said "h265 10-bit for
PQ/HLG input", which both of those contradict.

Outside values: the codec, pixel format and transfer of each written clip as PyAV (FFmpeg) reads them; the
sources are made by the ffmpeg command."""

from __future__ import annotations

import shutil
import subprocess

import pytest

from lenslab.cli.main import main

av = pytest.importorskip("av")
FFMPEG = shutil.which("ffmpeg")
pytestmark = pytest.mark.skipif(FFMPEG is None, reason="needs the ffmpeg command (CI installs Debian's)")


def _clip(path, pq: bool):
    """Two seconds of ffmpeg's test pattern, H.265 10-bit tagged PQ (BT.2020) or H.264 SDR, by Debian's ffmpeg."""
    codec = (["-c:v", "libx265", "-pix_fmt", "yuv420p10le", "-color_primaries", "bt2020", "-color_trc", "smpte2084",
              "-colorspace", "bt2020nc", "-x265-params", "log-level=none"] if pq
             else ["-c:v", "libx264", "-pix_fmt", "yuv420p"])
    subprocess.run([FFMPEG, "-v", "error", "-y", "-f", "lavfi", "-i", "testsrc=size=64x32:rate=5", "-t", "1", *codec,
                    str(path)], check=True, timeout=120)


def _written(path):
    with av.open(str(path)) as c:
        cc = c.streams.video[0].codec_context
        return cc.name, cc.pix_fmt, int(cc.color_trc)


def test_the_help_names_the_transfer_written(tmp_path, capsys):
    with pytest.raises(SystemExit):
        main(["warp", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert ".mp4 h264, or h265 10-bit for a clip written PQ or HLG (its input's transfer, or --display's)" in text
    pq, sdr = tmp_path / "pq.mp4", tmp_path / "sdr.mp4"
    _clip(pq, True)
    _clip(sdr, False)
    common = ["--from", "equirect", "--to", "equirect", "--size", "32x16", "-q"]
    assert main(["warp", str(pq), "-o", str(tmp_path / "a.mp4"), *common]) == 0
    assert _written(tmp_path / "a.mp4") == ("hevc", "yuv420p10le", 16)
    assert main(["warp", str(pq), "-o", str(tmp_path / "b.mp4"), "--display", "sRGB", *common]) == 0
    assert _written(tmp_path / "b.mp4")[:2] == ("h264", "yuv420p")
    assert main(["warp", str(sdr), "-o", str(tmp_path / "c.mp4"), "--display", "Rec.2100-PQ", *common]) == 0
    assert _written(tmp_path / "c.mp4") == ("hevc", "yuv420p10le", 16)
