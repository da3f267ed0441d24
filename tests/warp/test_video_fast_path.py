"""A clip warped by `lenslab warp` (compiled colour passes, decode and encode on threads) gives the frames that
warping its frames one by one as still images gives: the clip's frames written as EXR by `lenslab convert`,
each warped by `lenslab warp` as an image; the warped clip decoded by ffmpeg itself (the command-line tool, not
lenslab's PyAV) and taken to linear light by colour-science's Y'CbCr decoding and BT.1886 EOTF."""

from __future__ import annotations

import shutil
import subprocess

import colour
import numpy as np
import pytest

av = pytest.importorskip("av")

import lenslab.io as lio  # noqa: E402
from lenslab.cli.main import main  # noqa: E402
from tests.io.ycbcr_oracle import ycbcr_codes  # noqa: E402

W, H, N, SIDE = 96, 48, 3, 48
TO = "fisheye:fov=180"
pytestmark = pytest.mark.skipif(shutil.which("ffmpeg") is None, reason="needs the ffmpeg command (Debian's ffmpeg)")


def _make(path):
    """A smooth H.264 4:2:0 clip, BT.709 tags, codes in [0.05, 0.95] moving with the frame."""
    y, x = np.mgrid[0:H, 0:W]
    with av.open(str(path), "w") as c:
        s = c.add_stream("libx264", rate=25)
        s.width, s.height, s.pix_fmt = W, H, "yuv420p"
        cc = s.codec_context
        cc.color_trc = cc.color_primaries = cc.colorspace = 1
        cc.color_range = 1
        cc.options = {"crf": "4"}
        for i in range(N):
            v = np.stack([0.5 + 0.45 * np.sin(x / 9.0 + i), 0.5 + 0.45 * np.cos(y / 7.0 - i),
                          0.5 + 0.45 * np.sin((x + y) / 11.0 + 2 * i)], -1)
            f = av.VideoFrame.from_ndarray(np.round(v * 65535).astype(np.uint16), format="rgb48le")
            f = f.reformat(format="yuv420p", dst_colorspace="itu709", src_color_range="JPEG", dst_color_range="MPEG")
            f.pts = i
            for p in s.encode(f):
                c.mux(p)
        for p in s.encode():
            c.mux(p)


def _ffmpeg_linear(path, w, h):
    """Every frame of ``path`` (FFV1 10-bit 4:4:4) decoded by the ffmpeg command to its own Y'CbCr samples (no
    conversion: the format it holds), then colour-science's BT.709 limited-range decoding and BT.1886 EOTF
    (ffmpeg's own conversion to RGB, swscale, is 0.4 % low at white: :mod:`tests.io.ycbcr_oracle`)."""
    raw = subprocess.run(["ffmpeg", "-v", "error", "-i", str(path), "-pix_fmt", "yuv444p10le", "-f", "rawvideo", "-"],
                         check=True, capture_output=True).stdout
    planes = np.frombuffer(raw, np.uint16).reshape(-1, 3, h, w)
    return colour.models.eotf_BT1886(ycbcr_codes(np.moveaxis(planes, 1, -1), 10, 1, False), L_B=0, L_W=1)


@pytest.mark.slow
def test_clip_warp_equals_warping_its_frames_as_stills(tmp_path):
    _make(tmp_path / "in.mp4")
    assert main(["warp", str(tmp_path / "in.mp4"), "-o", str(tmp_path / "out.mkv"), "--to", TO, "--size",
                 f"{SIDE}x{SIDE}", "-q"]) == 0  # FFV1 10-bit 4:4:4 by .mkv: lossless but for 10-bit codes
    assert main(["convert", str(tmp_path / "in.mp4"), "--to", "exr", "-o", str(tmp_path / "frames"),
                 "--pixel-type", "float", "-q"]) == 0
    stills = []
    for i, exr in enumerate(sorted((tmp_path / "frames").iterdir())):
        out = tmp_path / f"still{i}.exr"
        assert main(["warp", str(exr), "-o", str(out), "--to", TO, "--size", f"{SIDE}x{SIDE}", "--pixel-type",
                     "float", "-q"]) == 0
        stills.append(lio.read(out)[0][..., :3])  # premultiplied colour: black outside the circle, as the clip
    got = _ffmpeg_linear(tmp_path / "out.mkv", SIDE, SIDE)
    assert len(got) == len(stills) == N
    for g, s in zip(got, stills):
        # FFV1 keeps the 10-bit codes: what differs is their rounding, half a luma step (1/876 of the range) plus
        # half a chroma step (1/896) through the BT.709 matrix (at most 1.86 for B): 0.0016 of the code range,
        # times the gamma-2.4 slope (at most 2.4): 0.0039 in linear light; both sides' matrices are exact (lenslab's
        # compiled passes, colour-science's decoding), so nothing else is allowed for. The mean is a tenth of that.
        np.testing.assert_allclose(g, s, atol=0.0039)
        assert np.abs(g - s).mean() < 0.001
