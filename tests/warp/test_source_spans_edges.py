"""The source pixels a cached plan reads (``WarpPlan.source_spans``) at the edges of what a clip's warp allows:
a view of one output pixel (two taps across, at the seam too), a view that sees nothing, sources other than an
equirect (no seam to wrap, odd widths), ffmpeg's v360 reading (``--compat v360``), and the decoder's
conversion of only those spans for every Y'CbCr layout at odd sizes. A source whose unread pixels are NaN warps
to the same bits as the whole source, all finite."""

from __future__ import annotations

import warnings
from fractions import Fraction

import numpy as np
import pytest

from lenslab.lenses import Camera
from lenslab.warp.batch import PlanCache

W, H = 192, 96


def _spans(src, dst, **options):
    cache = PlanCache(**options)
    return cache, cache.plan(src, dst).source_spans()


def _read(spans: np.ndarray, width: int) -> np.ndarray:
    cols = np.arange(width)[None, :]
    return ((cols >= spans[:, :1]) & (cols < spans[:, 1:2])) | ((cols >= spans[:, 2:3]) & (cols < spans[:, 3:]))


@pytest.mark.parametrize("yaw, columns", [(0.0, (95, 96)), (90.0, (143, 144)), (180.0, (191, 0))])
def test_a_one_pixel_view_reads_its_four_taps_only(yaw, columns):
    # conventions.md: longitude lon at x = (lon / 360 + 1/2) W - 1/2, latitude 0 at y = H/2 - 1/2: the centre of a
    # one-pixel view at yaw 0 is (95.5, 47.5), its taps columns 95 and 96 of rows 47 and 48; at yaw 90, 143.5; at
    # 180, 191.5: the last column and (across the seam) the first
    src = Camera.from_spec("equirect", (W, H))
    dst = Camera.from_spec("perspective:fov=1", (1, 1), yaw=yaw)
    spans = _spans(src, dst)[1]
    want = np.zeros((H, W), bool)
    want[47:49, list(columns)] = True
    np.testing.assert_array_equal(_read(spans, W), want)


def test_a_view_that_sees_nothing_reads_nothing():
    # a 90-degree fisheye sees the front only; a 60-degree view straight back has no ray in it
    src = Camera.from_spec("fisheye:fov=90", (64, 64))
    dst = Camera.from_spec("perspective:fov=60", (8, 8), yaw=180.0)
    cache, spans = _spans(src, dst)
    assert not spans.any() and cache.plan(src, dst).source_window() == (0, 0, 0, 0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the empty view's note
        colour, alpha = cache.warp_frame(np.full((64, 64, 3), np.nan, np.float32), src, dst)
    assert not colour.any() and not alpha.any()


SOURCES = {  # source spec and size (odd widths, no seam or no pole) -> views of it
    "fisheye source (no seam)": ("fisheye:fov=180", (97, 97)),
    "odd-width equirect": ("equirect", (97, 49)),
    "half-equirect": ("half-equirect", (65, 64)),
    "cylindrical": ("cylindrical", (95, 48)),
    "perspective source": ("perspective:fov=90", (63, 47)),
    "little planet": ("little-planet", (64, 64)),
}
VIEWS = [("perspective:fov=70", (33, 21), {}), ("fisheye:fov=180", (31, 31), {"yaw": 180.0, "pitch": 60.0}),
         ("equirect", (40, 20), {}), ("perspective:fov=20", (9, 9), {"pitch": 89.5})]


def _same_bits_without_unread(src, dst, **options):
    cache, spans = _spans(src, dst, **options)
    if spans is None:  # no taps (the whole frame is converted)
        return False
    image = np.random.default_rng(11).random((src.height, src.width, 3), dtype=np.float32) + 0.25
    holed = image.copy()
    holed[~_read(spans, src.width)] = np.nan
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # an empty view's note
        want, got = cache.warp_frame(image, src, dst), cache.warp_frame(holed, src, dst)
    for g, w in zip(got, want):
        assert np.isfinite(g).all()
        np.testing.assert_array_equal(g, w)
    return True


@pytest.mark.parametrize("name", list(SOURCES))
def test_unread_pixels_of_other_sources_are_never_read(name):
    spec, size = SOURCES[name]
    src = Camera.from_spec(spec, size)
    kept = [_same_bits_without_unread(src, Camera.from_spec(v, s, **pose)) for v, s, pose in VIEWS]
    assert any(kept)  # some view of each source is drawn from taps


@pytest.mark.parametrize("spec, pose", [("fisheye:fov=180", {"yaw": 179.7}), ("perspective:fov=40", {"pitch": 88.0}),
                                        ("perspective:fov=60", {"yaw": -100.0})])
def test_ffmpeg_v360_reading_reads_only_its_spans(spec, pose):
    from lenslab.warp.compat_v360 import V360Plan

    src, dst = Camera.from_spec("equirect", (W, H)), Camera.from_spec(spec, (41, 41), **pose)
    assert _same_bits_without_unread(src, dst, factory=V360Plan)


@pytest.mark.parametrize("pix_fmt", ["yuv420p", "yuv422p", "yuv444p", "yuv420p10le", "yuv422p10le", "yuv444p12le"])
@pytest.mark.parametrize("size", [(33, 17), (1, 3), (65, 2)])
def test_a_frame_converted_in_spans_has_the_whole_frames_bits_there(pix_fmt, size):
    pytest.importorskip("av")
    from lenslab.io.video import VideoInfo
    from lenslab.io.video.ycbcr import FORMATS, planes, ycbcr_frame, ycbcr_to_linear, ycbcr_to_linear_reference

    w, h = size
    frame = ycbcr_frame(w, h, pix_fmt)
    rng = np.random.default_rng(3)
    bits = FORMATS[pix_fmt][0]
    for p in planes(frame):  # codes within the legal range of their depth
        p[...] = rng.integers(16 << (bits - 8), 236 << (bits - 8), p.shape).astype(p.dtype)
    info = VideoInfo(w, h, Fraction(24), 1, "h264", pix_fmt)
    whole = ycbcr_to_linear(frame, info)
    # the whole frame's pass against the NumPy reference: float32 table lookups summed in another order, a few
    # float32 steps of values up to 1 apart at most
    ref = ycbcr_to_linear_reference(*[np.asarray(p) for p in planes(frame)], info, pix_fmt, (h, w))
    np.testing.assert_allclose(whole, ref, rtol=1e-5, atol=1e-7)
    for _ in range(8):  # spans of any parity, starting and ending inside a chroma sample's columns
        spans = np.sort(rng.integers(0, w + 1, (h, 4)), axis=1).astype(np.int64)
        got = ycbcr_to_linear(frame, info, spans, np.full((h, w, 3), np.nan, np.float32))
        read = _read(spans, w)
        assert np.isnan(got[~read]).all()  # not written
        np.testing.assert_array_equal(got[read], whole[read])  # the whole frame's bits
