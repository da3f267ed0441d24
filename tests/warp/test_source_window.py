"""A plan's source window (the pixels its cached taps read), which a video decoder converts alone: its columns
for an equirect source seen by a forward 180-degree fisheye are the front hemisphere by the pixel-centre formula,
and a frame converted only there warps to the same bits as the whole frame."""

from __future__ import annotations

from fractions import Fraction

import numpy as np

from lenslab.io.video import VideoInfo
from lenslab.io.video.colour import codes16_to_linear_compiled
from lenslab.lenses import Camera
from lenslab.warp.batch import PlanCache

W, H = 192, 96


def _plan(cache, src, dst):
    cache.warp_frame(np.zeros((src.height, src.width, 3), np.float32), src, dst)  # the taps are kept now
    return cache.plan(src, dst)


def test_fisheye_reads_the_front_hemisphere_of_an_equirect():
    src, dst = Camera.from_spec("equirect", (W, H)), Camera.from_spec("fisheye:fov=180", (H, H))
    # longitude -90..90 degrees at x = (lon / 360 + 1/2) W - 1/2 (pixel centres at half-integers, conventions.md):
    # x from W/4 - 1/2 to 3W/4 - 1/2, so the left taps from floor(W/4 - 1/2) = W/4 - 1 and the right ones to 3W/4,
    # one past it 3W/4 + 1; every latitude is seen (the circle reaches both poles)
    assert _plan(PlanCache(), src, dst).source_window() == (0, H, W // 4 - 1, 3 * W // 4 + 1)


def test_a_view_across_the_seam_reads_both_edges():
    src = Camera.from_spec("equirect", (W, H))
    dst = Camera.from_spec("fisheye:fov=180", (H, H), yaw=180.0)  # looking backwards: the seam is in view
    window = _plan(PlanCache(), src, dst).source_window()
    # None where a pixel's taps straddle the seam (the folding sampler reads both edges), else every column
    assert window is None or window[2:] == (0, W)


def test_a_frame_converted_in_the_window_warps_to_the_same_bits():
    src, dst = Camera.from_spec("equirect", (W, H)), Camera.from_spec("fisheye:fov=120", (80, 80), yaw=30.0, pitch=10.0)
    cache = PlanCache()
    window = _plan(cache, src, dst).source_window()
    assert window is not None and window[3] - window[2] < W  # part of the frame only
    info = VideoInfo(W, H, Fraction(24), 1, "h264", "yuv420p")
    codes = np.random.default_rng(3).integers(0, 65536, (H, W, 3), dtype=np.uint16)
    part = codes16_to_linear_compiled(codes, info, window)
    whole = codes16_to_linear_compiled(codes, info)
    r0, r1, c0, c1 = window
    assert not part[:, :c0].any() and not part[:, c1:].any() and not part[:r0].any() and not part[r1:].any()
    np.testing.assert_array_equal(part[r0:r1, c0:c1], whole[r0:r1, c0:c1])
    for got, want in zip(cache.warp_frame(part, src, dst), cache.warp_frame(whole, src, dst)):
        np.testing.assert_array_equal(got, want)
