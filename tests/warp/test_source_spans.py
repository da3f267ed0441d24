"""The source pixels a cached plan reads, row by row (``WarpPlan.source_spans``), which a video decoder converts
alone: every other source pixel is never read, across the seam and over the poles too (the folding sampler's
taps included). A source whose unread pixels are NaN warps to the same bits as the whole source, all finite; a
Y'CbCr frame decoded only in the spans, into a buffer of NaN, does the same. The spans of a forward 180-degree
fisheye are the front hemisphere by the pixel-centre formula (conventions.md)."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

from lenslab.lenses import Camera
from lenslab.warp.batch import PlanCache

W, H = 192, 96

GEOMETRIES = {
    "front": ("fisheye:fov=180", (H, H), {}),
    "across the seam": ("fisheye:fov=180", (101, 101), {"yaw": 179.7}),  # the seam in view: taps wrap
    "over the pole": ("fisheye:fov=150", (80, 80), {"pitch": 90.0}),  # the zenith in view: taps fold
    # every pixel's taps straddle the seam (or the pole): only the folding sampler reads the source
    "at the seam only": ("perspective:fov=2", (3, 3), {"yaw": 180.0}),
    "at the pole only": ("perspective:fov=2", (3, 3), {"pitch": 90.0}),
    "tilted narrow": ("fisheye:fov=120", (80, 80), {"yaw": 30.0, "pitch": 10.0}),
    "perspective": ("perspective:fov=60", (64, 48), {"yaw": -100.0, "pitch": -35.0}),
}


def _plan(src, dst):
    cache = PlanCache()
    cache.warp_frame(np.zeros((src.height, src.width, 3), np.float32), src, dst)  # the taps are kept now
    return cache, cache.plan(src, dst)


def _unread(spans: np.ndarray) -> np.ndarray:
    cols = np.arange(W)[None, :]
    return ~(((cols >= spans[:, :1]) & (cols < spans[:, 1:2])) | ((cols >= spans[:, 2:3]) & (cols < spans[:, 3:])))


@pytest.mark.parametrize("name", list(GEOMETRIES))
def test_pixels_outside_the_spans_are_never_read(name):
    spec, size, pose = GEOMETRIES[name]
    src, dst = Camera.from_spec("equirect", (W, H)), Camera.from_spec(spec, size, **pose)
    cache, plan = _plan(src, dst)
    spans = plan.source_spans()
    assert spans.shape == (H, 4) and spans.dtype == np.int64
    unread = _unread(spans)
    assert unread.any()  # every geometry here reads part of the source only
    image = np.random.default_rng(5).random((H, W, 3), dtype=np.float32) * 4
    holed = image.copy()
    holed[unread] = np.nan
    want = cache.warp_frame(image, src, dst)
    got = cache.warp_frame(holed, src, dst)
    for g, w in zip(got, want):
        assert np.isfinite(g).all()
        np.testing.assert_array_equal(g, w)
    r0, r1, c0, c1 = plan.source_window()  # the box around the spans
    rows, cols = np.nonzero(~unread)
    assert (r0, r1, c0, c1) == (rows.min(), rows.max() + 1, cols.min(), cols.max() + 1)


def test_front_fisheye_spans_are_the_front_hemisphere():
    src, dst = Camera.from_spec("equirect", (W, H)), Camera.from_spec("fisheye:fov=180", (H, H))
    spans = _plan(src, dst)[1].source_spans()
    # at the equator the view spans longitude -90..90 degrees, x = (lon / 360 + 1/2) W - 1/2: from W/4 - 1/2 to
    # 3W/4 - 1/2, so the taps from floor(W/4 - 1/2) = W/4 - 1 to 3W/4, one past it 3W/4 + 1
    for j in (H // 2 - 1, H // 2):
        assert tuple(spans[j]) == (W // 4 - 1, 3 * W // 4 + 1, 0, 0)
    # every row is read (the circle reaches both poles), none beyond those columns
    assert (spans[:, 1] > spans[:, 0]).all()
    assert spans[:, 0].min() == W // 4 - 1 and spans[:, 1].max() == 3 * W // 4 + 1


def test_a_view_across_the_seam_reads_both_sides_of_it_only():
    src = Camera.from_spec("equirect", (W, H))
    dst = Camera.from_spec("fisheye:fov=180", (H, H), yaw=180.0)  # the back hemisphere: longitude 90..270 degrees
    spans = _plan(src, dst)[1].source_spans()
    # by the same formula, the equator's taps run from column 3W/4 - 1 to the last and from the first to W/4: two
    # spans, the front hemisphere between them left out
    for j in (H // 2 - 1, H // 2):
        assert tuple(spans[j]) == (0, W // 4 + 1, 3 * W // 4 - 1, W)


@pytest.mark.parametrize("name", ["front", "across the seam", "over the pole", "at the seam only"])
def test_a_frame_decoded_in_the_spans_warps_to_the_whole_frames_bits(name):
    pytest.importorskip("av")
    from lenslab.io.video import VideoInfo
    from lenslab.io.video.ycbcr import planes, ycbcr_frame, ycbcr_to_linear

    spec, size, pose = GEOMETRIES[name]
    src, dst = Camera.from_spec("equirect", (W, H)), Camera.from_spec(spec, size, **pose)
    cache, plan = _plan(src, dst)
    spans = plan.source_spans()
    frame = ycbcr_frame(W, H, "yuv420p")
    rng = np.random.default_rng(7)
    for p in planes(frame):
        p[...] = rng.integers(16, 236, p.shape, dtype=np.uint8)
    info = VideoInfo(W, H, Fraction(24), 1, "h264", "yuv420p")
    whole = ycbcr_to_linear(frame, info)
    part = ycbcr_to_linear(frame, info, spans, np.full((H, W, 3), np.nan, np.float32))
    unread = _unread(spans)
    assert np.isnan(part[unread]).all()  # not written
    np.testing.assert_array_equal(part[~unread], whole[~unread])
    for g, w in zip(cache.warp_frame(part, src, dst), cache.warp_frame(whole, src, dst)):
        assert np.isfinite(g).all()
        np.testing.assert_array_equal(g, w)
