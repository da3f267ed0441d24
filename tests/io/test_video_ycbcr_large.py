"""The compiled decoding of large 8-bit frames (R' and B' from 256 x 256 tables, G' by a lookup a pixel: many chroma
rows and columns, bands on threads) against colour-science's Y'CbCr decoding and BT.1886 EOTF in float64, and against
the NumPy reference; the encoding of a frame wider than eight pixels (eight at a time where the CPU can) against the
NumPy reference."""

from __future__ import annotations

from fractions import Fraction

import colour
import numpy as np
import pytest

av = pytest.importorskip("av")

from lenslab.io.video import VideoInfo  # noqa: E402
from lenslab.io.video.ycbcr import (linear_to_ycbcr, linear_to_ycbcr_reference, planes,  # noqa: E402
                                    ycbcr_to_linear, ycbcr_to_linear_reference)
from tests.io.test_video_ycbcr import _decode_bound  # noqa: E402

H, W = 515, 611  # odd: the last chroma blocks are partial


@pytest.mark.parametrize("fmt,matrix,rng", [("yuv420p", 1, 1), ("yuv444p", 5, 2), ("yuv422p", 1, 1)])
def test_large_8bit_frames_decode_as_colour_science(fmt, matrix, rng):
    info = VideoInfo(W, H, Fraction(25), 1, "h264", fmt, 1, 1, matrix, rng)
    frame = av.VideoFrame(W, H, fmt)
    rs = np.random.default_rng(5)
    for p in planes(frame):
        p[:] = rs.integers(0, 256, p.shape)
    y, u, v = planes(frame)
    hx, vy = (1, 1) if fmt == "yuv420p" else ((1, 0) if fmt == "yuv422p" else (0, 0))
    up = [np.repeat(np.repeat(c, 1 << vy, 0), 1 << hx, 1)[:H, :W] for c in (u, v)]
    ycc = np.stack([y[:H, :W], *up], -1).astype(np.float64)
    k = colour.WEIGHTS_YCBCR["ITU-R BT.709" if matrix == 1 else "ITU-R BT.601"]
    rgb = colour.YCbCr_to_RGB(ycc, K=k, in_bits=8, in_legal=rng == 1, in_int=True)
    want = colour.models.eotf_BT1886(np.clip(rgb, 0.0, 1.0), L_B=0, L_W=1)
    got = ycbcr_to_linear(frame, info)
    bound = _decode_bound(rgb, 1)  # the same arithmetic bound as the small frames' test
    assert (np.abs(got - want) <= bound).all()
    ref = ycbcr_to_linear_reference(y, u, v, info, fmt, (H, W))
    assert (np.abs(got - ref) <= 2 * bound).all()
    # a window (odd corners) is the whole frame's pixels
    out = np.zeros((H, W, 3), np.float32)
    ycbcr_to_linear(frame, info, (1, H - 2, 3, W - 1), out)
    np.testing.assert_array_equal(out[1:H - 2, 3:W - 1], got[1:H - 2, 3:W - 1])


@pytest.mark.parametrize("fmt", ["yuv420p", "yuv420p10le", "yuv444p"])
def test_wide_frames_encode_as_the_reference(fmt):
    info = VideoInfo(W, H, Fraction(25), 1, "h264", fmt, 1, 1, 1, 1)
    rs = np.random.default_rng(6)
    lin = (rs.uniform(-0.1, 1.3, (H, W, 3)) ** 3).astype(np.float32)  # dark values dense, some outside [0, 1]
    lin[0, :5] = [[np.nan, 0, 1], [np.inf, -np.inf, 0], [1, 1, 1], [0, 0, 0], [np.nan, np.nan, np.inf]]
    got = planes(linear_to_ycbcr(lin, info, fmt))
    for g, r in zip(got, linear_to_ycbcr_reference(lin, info, fmt)):
        # the inverse curve's table may flip a code whose exact value lies within 0.001 of a half
        # (tests/io/test_video_ycbcr.py); nothing else differs
        d = np.abs(g[:r.shape[0], :r.shape[1]].astype(np.int64) - r)
        assert d.max() <= 1 and (d > 0).mean() < 1e-3
