"""Exact geometry of the warp: identity, one-column yaw shifts, the seam and the poles."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lenslab.lenses import Camera
from lenslab.warp import FILTERS, warp

RNG = np.random.default_rng(5)
NOISE = RNG.random((32, 64, 3), dtype=np.float32) * 10.0  # rough HDR content: any misstep shows


def eq(w, h, **pose):
    return Camera.from_spec("equirect", (w, h), **pose)


@pytest.mark.parametrize("filt", FILTERS)
def test_identity_is_exact(filt):
    # every filter's weights at a pixel centre are (1, 0, ...): the output must be the input, bit for bit
    src = eq(64, 32)
    out, alpha = warp(NOISE, src, src, filter=filt)
    np.testing.assert_array_equal(out, NOISE)
    np.testing.assert_array_equal(alpha, 1.0)


def test_identity_exact_map_and_lattice_agree():
    src = eq(256, 128)
    img = RNG.random((128, 256, 3), dtype=np.float32)
    for exact in (False, True):
        out, _ = warp(img, src, src, exact_map=exact)
        np.testing.assert_array_equal(out, img)


@settings(max_examples=12, deadline=None)
@given(k=st.integers(-70, 70), filt=st.sampled_from(FILTERS))
def test_yaw_by_whole_columns_rolls_exactly(k, filt):
    # yaw turns right: the output's column c shows the source's column c + k (mod W)
    w = 64
    out, alpha = warp(NOISE, eq(w, 32), eq(w, 32, yaw=360.0 * k / w), filter=filt)
    np.testing.assert_allclose(out, np.roll(NOISE, -k, axis=1), rtol=0, atol=2e-5)  # float32 of the map
    np.testing.assert_array_equal(alpha, 1.0)


def test_one_column_shift_is_bit_exact():
    out, _ = warp(NOISE, eq(64, 32), eq(64, 32, yaw=360.0 / 64))
    np.testing.assert_array_equal(out, np.roll(NOISE, -1, axis=1))


def smooth_pano(w, h):
    cam = eq(w, h)
    _, d, _ = cam.rays(samples=1, seed=None)
    d = d[:, :, 0]
    f = np.stack([1 + d[..., 0] * d[..., 1] + 0.5 * d[..., 2], 2 + d[..., 1] ** 3, 1 + np.sin(2 * d[..., 0])], -1)
    return f.astype(np.float32), cam


def smooth_truth(cam):
    _, d, v = cam.rays(samples=1, seed=None)
    d = d[:, :, 0]
    return np.stack([1 + d[..., 0] * d[..., 1] + 0.5 * d[..., 2], 2 + d[..., 1] ** 3, 1 + np.sin(2 * d[..., 0])], -1)


@pytest.mark.parametrize("filt", FILTERS)
@pytest.mark.parametrize("look", [dict(yaw=180.0), dict(pitch=90.0), dict(pitch=-90.0), dict(pitch=89.0, yaw=180.0)])
def test_seam_and_poles_show_no_line(filt, look):
    """A view across the seam or straight at a pole matches the smooth truth everywhere: no seam line,
    no pole pinch, no NaN."""
    img, src = smooth_pano(256, 128)
    dst = Camera.from_spec("perspective:fov=100", (64, 64), **look)
    out, alpha = warp(img, src, dst, filter=filt)
    assert np.isfinite(out).all()
    np.testing.assert_array_equal(alpha, 1.0)
    err = np.abs(out - smooth_truth(dst))
    # the smooth function's curvature over one source pixel (1.4 deg) gives bilinear errors ~1e-3; nearest
    # is off by up to half a pixel of gradient (~0.02). A wrong fold at the seam or the pole reads a texel
    # up to 180 deg away and costs ~0.5-2.
    bound = 0.03 if filt == "nearest" else 3e-3
    assert err.max() < bound, err.max()
    # and no single row or column stands out (a line would)
    assert err.mean(axis=(0, 2)).max() < 4 * err.mean() + 1e-4
    assert err.mean(axis=(1, 2)).max() < 4 * err.mean() + 1e-4


@pytest.mark.parametrize("filt", FILTERS)
def test_view_across_seam_equals_rolled_panorama(filt):
    # the same view at yaw 180 (across the seam) and at yaw 0 of the panorama rolled by half a turn
    w, h = 128, 64
    img = RNG.random((h, w, 3), dtype=np.float32)
    src = eq(w, h)
    for spec in ("fisheye:fov=120", "perspective:fov=90"):
        a, aa = warp(img, src, Camera.from_spec(spec, (48, 48), yaw=180.0, pitch=20.0), filter=filt)
        b, ab = warp(np.roll(img, w // 2, axis=1), src, Camera.from_spec(spec, (48, 48), pitch=20.0), filter=filt)
        # the two maps differ only by float32 rounding of x (1e-5 px) times the gradient of noise (~1/px)
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-4)
        np.testing.assert_array_equal(aa, ab)


def test_pole_fold_reads_the_opposite_meridian():
    # a single bright texel in the top row, column 3: looking up just past the pole (pitch 90) its
    # bilinear footprint must appear on both sides of the pole, read through the fold
    w, h = 16, 8
    img = np.zeros((h, w, 1), np.float32)
    img[0, 3] = 1.0
    src = eq(w, h)
    # a source point half a row above the top row's centre, on column 3 + W/2: folds onto (3, 0)
    from lenslab.warp.filters import sample
    from lenslab.warp.seam import border_of
    xs = np.array([[[3.0 + w / 2, 3.0 + w / 2]]], np.float32)
    ys = np.array([[[-0.5, -1.0]]], np.float32)
    out = np.zeros((1, 1, 1), np.float32)
    alpha = np.zeros((1, 1), np.float32)
    sample(img, xs, ys, np.ones((1, 1, 2), bool), border_of(src.lens), "bilinear", out, alpha)
    # y = -0.5: halfway between row 0 on the far meridian (the texel itself after the fold) and row 0
    # of column 11 (zero): 0.5; y = -1.0 is row 0 folded = the texel: 1.0; mean of the two samples 0.75
    assert out[0, 0, 0] == pytest.approx(0.75)


def test_padded_copy_matches_the_folded_taps():
    # seam.pad (for code that wants plain arrays) agrees with the samplers' per-tap folding
    from lenslab.warp.seam import border_of, pad

    src = eq(64, 32)
    padded = pad(NOISE, border_of(src.lens), 3)
    assert padded.shape == (38, 70, 3)
    np.testing.assert_array_equal(padded[3:-3, 3:-3], NOISE)
    np.testing.assert_array_equal(padded[3:-3, :3], NOISE[:, -3:])  # wrapped columns at the seam
    # row -1 is row 0 half a turn away; row -2 is row 1 there
    np.testing.assert_array_equal(padded[2, 3:-3], np.roll(NOISE[0], -32, axis=0))
    np.testing.assert_array_equal(padded[1, 3:-3], np.roll(NOISE[1], -32, axis=0))
    np.testing.assert_array_equal(padded[-1, 3:-3], np.roll(NOISE[-3], -32, axis=0))
    # a perspective source clamps to its edge
    persp = pad(NOISE, border_of(Camera.from_spec("perspective", (64, 32)).lens), 2)
    np.testing.assert_array_equal(persp[0, 2:-2], NOISE[0])


def v360_equirect_resample(img: np.ndarray, w_out: int, h_out: int) -> np.ndarray:
    """What ffmpeg 5.1's ``v360=e:e:interp=line`` gives for an equirect-to-equirect resize, in float64.

    Measured with a source whose values encode their coordinates (tests/warp/test_v360_ffmpeg.py compares
    the real filter): v360 samples the output's pixel centres, ``p = (i + 1/2) W / w_out`` in source
    pixels, and reads the source at index ``p (W - 1) / W`` (its [-1, 1] spans the first to the last
    pixel centre), bilinearly, columns wrapping and rows clamped.
    """
    h, w = img.shape[:2]
    ix = (np.arange(w_out) + 0.5) * w / w_out * (w - 1) / w
    iy = (np.arange(h_out) + 0.5) * h / h_out * (h - 1) / h
    x0, y0 = np.floor(ix).astype(int), np.floor(iy).astype(int)
    fx, fy = (ix - x0)[None, :, None], (iy - y0)[:, None, None]
    xa, xb = x0 % w, (x0 + 1) % w
    ya, yb = np.clip(y0, 0, h - 1), np.clip(y0 + 1, 0, h - 1)
    f = img.astype(np.float64)
    top = f[ya][:, xa] * (1 - fx) + f[ya][:, xb] * fx
    bottom = f[yb][:, xa] * (1 - fx) + f[yb][:, xb] * fx
    return top * (1 - fy) + bottom * fy


def test_v360_compat_reproduces_its_half_pixel_convention():
    from lenslab.warp.compat_v360 import v360_plan

    src = eq(64, 32)
    # same size: v360 reads index (i + 1/2)(W - 1)/W, not pixel i: the identity blurs, as ffmpeg's does
    out, _ = v360_plan(src, src).run(NOISE)
    np.testing.assert_allclose(out, v360_equirect_resample(NOISE, 64, 32), rtol=0, atol=2e-5)  # float32 map
    # a 2x reduction: v360 reads index (2i + 1)(W - 1)/W; lenslab averages pixels 2i and 2i + 1
    small = eq(32, 16)
    out, _ = v360_plan(src, small).run(NOISE)
    np.testing.assert_allclose(out, v360_equirect_resample(NOISE, 32, 16), rtol=0, atol=2e-5)
    ours, _ = warp(NOISE, src, small)
    np.testing.assert_allclose(ours[2:-2], 0.25 * (NOISE[::2, ::2] + NOISE[1::2, ::2] + NOISE[::2, 1::2]
                                                   + NOISE[1::2, 1::2])[2:-2], rtol=0, atol=2e-5)


def _smooth_panorama(w, h):
    """A smooth function of direction sampled at the pixel centres of a w x h equirect."""
    lon = (np.arange(w) + 0.5) / w * 2 * np.pi - np.pi
    lat = np.pi / 2 - (np.arange(h) + 0.5) / h * np.pi
    lo, la = np.meshgrid(lon, lat)
    f = 1.0 + 0.5 * np.cos(3 * lo) * np.cos(la) + 0.3 * np.sin(2 * la)
    return np.repeat(f[..., None], 3, axis=2).astype(np.float32)


@pytest.mark.parametrize("samples", [1, 4])
def test_antialias_cube_faces_are_measured_inside_their_face(samples):
    # A footprint measured across a cube-map face seam spans two faces' directions and averages the
    # wrong region: the border pixels of every face would stand out. Measured inside the face, they
    # match a dense supersampling as well as the rest do.
    img = _smooth_panorama(512, 256)
    src = eq(512, 256)
    dst = Camera.from_spec("cubemap", (96, 64), yaw=10, pitch=-5)
    ref = warp(img, src, dst, samples=64)[0]
    out = warp(img, src, dst, antialias=True, samples=samples)[0]
    err = np.abs(out - ref)[..., 0] / np.abs(ref[..., 0])
    x, y = np.arange(96) % 32, np.arange(64) % 32
    border = np.minimum.outer(np.minimum(y, 31 - y), np.minimum(x, 31 - x)) == 0
    # measured (mean relative error, border / interior): 5e-5 / 1.2e-4 with one sample, 1.4e-5 / 4e-5 with
    # 2x2; measured across the seam: 0.10 and 0.05 on the border
    assert err[border].mean() <= 3 * err[~border].mean() + 1e-3


def test_threads_change_nothing():
    # bands run one per thread: the output must not depend on how many there are
    from lenslab.warp.kernels.dispatch import set_threads

    img = _smooth_panorama(256, 128)
    src = eq(256, 128)
    dst = Camera.from_spec("fisheye:fov=180", (96, 96))
    try:
        set_threads(1)
        one = [warp(img, src, dst, antialias=a, band_points=1000) for a in (False, True)]
        set_threads(4)  # more threads than this machine may have cores: bands still interleave
        many = [warp(img, src, dst, antialias=a, band_points=1000) for a in (False, True)]
    finally:
        set_threads(None)
    for (a, aa), (b, ba) in zip(one, many):
        np.testing.assert_array_equal(a, b)
        np.testing.assert_array_equal(aa, ba)


@pytest.mark.parametrize("samples", [1, 4])
def test_antialias_across_seam_equals_rolled_panorama(samples):
    # the footprint of a pixel whose neighbours lie across the seam is measured unwrapped: the view at
    # yaw 180 equals the view at yaw 0 of the panorama rolled by half a turn (a footprint measured
    # across the seam would span the whole panorama and average it, a visible line)
    w, h = 128, 64
    img = RNG.random((h, w, 3), dtype=np.float32)
    src = eq(w, h)
    for spec in ("fisheye:fov=120", "perspective:fov=90"):
        kw = dict(antialias=True, samples=samples)
        a, aa = warp(img, src, Camera.from_spec(spec, (48, 48), yaw=180.0, pitch=20.0), **kw)
        b, ab = warp(np.roll(img, w // 2, axis=1), src, Camera.from_spec(spec, (48, 48), pitch=20.0), **kw)
        # float32 rounding of x (1e-5 px) moves box edges and weights by as little
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-4)
        np.testing.assert_allclose(aa, ab, rtol=0, atol=1e-6)
