"""A clip longer than the buffers reused from frame to frame (the decoded source, the warp's output, the encoder's
ring of Y'CbCr frames) is warped frame by frame as its own frames are: each output frame of `lenslab warp` against lenslab.warp.warp of the input frame decoded
independently (colour-science's Y'CbCr decoding and BT.1886 EOTF), so a frame overwritten too early would show."""

from __future__ import annotations

import colour
import numpy as np
import pytest

av = pytest.importorskip("av")

from lenslab.cli.main import main  # noqa: E402
from lenslab.lenses import Camera  # noqa: E402
from lenslab.warp import warp  # noqa: E402
from tests.io.ycbcr_oracle import decode_codes, write_ffv1  # noqa: E402

W, H, N, SIDE = 64, 32, 11, 24  # more frames than any ring (the encoder's 3 Y'CbCr frames)
TO = "fisheye:fov=180"


def _make(path):
    y, x = np.mgrid[0:H, 0:W]
    write_ffv1(path, [np.stack([0.5 + 0.45 * np.sin((x + 3 * i) / 6.0), 0.5 + 0.45 * np.cos(y / 5.0 - i),
                                np.full((H, W), 0.05 + 0.9 * i / N)], -1) for i in range(N)])


@pytest.mark.slow
def test_every_frame_of_a_long_clip_is_its_own(tmp_path):
    _make(tmp_path / "in.mkv")
    assert main(["warp", str(tmp_path / "in.mkv"), "-o", str(tmp_path / "out.mkv"), "--to", TO, "--size",
                 f"{SIDE}x{SIDE}", "-q"]) == 0
    src = Camera.from_spec("equirect", (W, H))
    dst = Camera.from_spec(TO, (SIDE, SIDE))
    want = [warp(colour.models.eotf_BT1886(c, L_B=0, L_W=1).astype(np.float32), src, dst)[0]
            for c in decode_codes(tmp_path / "in.mkv")]
    got = [colour.models.eotf_BT1886(c, L_B=0, L_W=1) for c in decode_codes(tmp_path / "out.mkv")]
    assert len(got) == len(want) == N
    for g, w in zip(got, want):
        # the output's 10-bit codes: half a luma step (1/876) plus half a chroma step (1/896) through the BT.709
        # matrix (at most 1.86), times the gamma-2.4 slope (at most 2.4): 0.0039; plus 1e-5 for the float32
        # decoding and warp. A frame of another time differs by 0.08 or more (the blue ramp's step).
        np.testing.assert_allclose(g, w, atol=0.0039 + 1e-5)


def test_reused_encoder_frames_keep_every_frame(tmp_path):
    """The writer reuses one Y'CbCr frame: x264 (lossless here, qp 0, with its 40-frame lookahead) must have
    taken each frame's samples before the next overwrites them. Each decoded frame's samples are the NumPy
    reference encoding's (colour-science's inverse EOTF, the BT.709 matrix), within the one code its table may
    flip at a half."""
    from fractions import Fraction

    from lenslab.io.video import VideoInfo, VideoWriter
    from lenslab.io.video.ycbcr import linear_to_ycbcr_reference

    info = VideoInfo(W, H, Fraction(25), N, "h264", "yuv420p")
    y, x = np.mgrid[0:H, 0:W]
    frames = [np.stack([x / W, y / H, np.full((H, W), i / N)], -1).astype(np.float32) for i in range(N)]
    writer = VideoWriter(tmp_path / "o.mp4", info, codec="h264")
    writer.stream.codec_context.options = {"qp": "0"}
    with writer:
        for f in frames:
            writer.write(f)
    with av.open(str(tmp_path / "o.mp4")) as c:
        got = [[np.asarray(p).reshape(p.height, p.line_size)[:, :p.width] for p in f.planes]
               for f in c.decode(video=0)]
    assert len(got) == N
    for g, f in zip(got, frames):
        for plane, want in zip(g, linear_to_ycbcr_reference(f, info, "yuv420p")):
            assert np.abs(plane.astype(np.int64) - want).max() <= 1
