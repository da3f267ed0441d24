"""The warp API: errors that explain, parallax, banding, caching, maps, dtypes, premultiplication."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lenslab.errors import WarpError
from lenslab.lenses import REGISTRY, Camera, make_lens
from lenslab.lenses.core.pose import Pose
from lenslab.warp import ParallaxWarning, WarpPlan, exact_map, warp, warp_tiles
from lenslab.warp.maps import Mapper, sample_pattern

RNG = np.random.default_rng(7)


def pano(w=128, h=64, c=3):
    return RNG.random((h, w, c), dtype=np.float32) * 4 - 1, Camera.from_spec("equirect", (w, h))


def test_lenslab_warp_is_callable_and_is_the_function():
    import lenslab
    import lenslab.warp

    img, src = pano()
    dst = Camera.from_spec("fisheye:fov=180", (32, 32))
    a = lenslab.warp(img, src, dst)[0]
    np.testing.assert_array_equal(a, lenslab.warp.warp(img, src, dst)[0])


def test_values_are_never_clamped_and_stay_float32():
    img, src = pano()
    img[28:36, 60:68] = 5000.0  # a sun, straight ahead
    dst = Camera.from_spec("perspective:fov=60", (48, 32))
    for filt in ("nearest", "bilinear", "bicubic", "lanczos"):
        out, alpha = warp(img.astype(np.float64), src, dst, filter=filt)
        assert out.dtype == np.float32 and alpha.dtype == np.float32
        assert out.max() > 1000 and out.min() < 0  # HDR highs and negative values pass through


def test_grey_2d_image_keeps_its_shape():
    img, src = pano(c=1)
    out, alpha = warp(img[..., 0], src, Camera.from_spec("fisheye", (24, 24)))
    assert out.shape == (24, 24) and alpha.shape == (24, 24)


@pytest.mark.parametrize("kwargs, message", [
    (dict(filter="cubic"), "unknown filter"),
    (dict(samples=0), "samples per pixel"),
    (dict(samples="many"), "whole number"),
])
def test_bad_options_explain(kwargs, message):
    img, src = pano()
    with pytest.raises(WarpError, match=message):
        warp(img, src, src, **kwargs)


def test_wrong_image_size_explains():
    img, _ = pano()
    with pytest.raises(WarpError, match="128x64 but the source camera is 64x32"):
        warp(img, Camera.from_spec("equirect", (64, 32)), Camera.from_spec("fisheye", (8, 8)))


def test_parallax_is_an_error_unless_allowed():
    img, src = pano()
    dst = Camera.from_spec("perspective", (16, 16), eye=(0.5, 0, 0))
    with pytest.raises(WarpError, match="parallax"):
        warp(img, src, dst)
    with pytest.warns(ParallaxWarning, match="parallax"):
        out, _ = warp(img, src, dst, allow_parallax=True)
    # allowed: the same result as from the source's eye
    np.testing.assert_array_equal(out, warp(img, src, Camera.from_spec("perspective", (16, 16)))[0])


def test_tiled_output_tiles_at_other_eyes_need_one_source_each():
    img, src = pano()
    tiles = [{"lens": "perspective:fov=90", "yaw": 90.0 * k, "eye": [0.1 * k, 0, 0]} for k in range(4)]
    dst = Camera(make_lens({"model": "tiled", "grid": "2x2", "tiles": tiles}, (64, 64)))
    with pytest.raises(WarpError, match="parallax"):
        warp(img, src, dst)
    # one panorama per eye: each tile is the plain warp of its own source from a camera at that eye
    srcs = [Camera(src.lens, Pose(eye=(0.1 * k, 0, 0))) for k in range(4)]
    imgs = [np.roll(img, 7 * k, axis=1) for k in range(4)]
    out, alpha = warp_tiles(imgs, srcs, dst)
    np.testing.assert_array_equal(alpha, 1.0)
    for k in range(4):
        x0, y0 = (k % 2) * 32, (k // 2) * 32
        one = Camera.from_spec("perspective:fov=90", (32, 32), yaw=90.0 * k, eye=(0.1 * k, 0, 0))
        np.testing.assert_array_equal(out[y0:y0 + 32, x0:x0 + 32], warp(imgs[k], srcs[k], one)[0])


def test_tiled_output_from_one_panorama_matches_per_tile_warps():
    img, src = pano()
    dst = Camera.from_spec("tiled:2x2", (64, 64), yaw=10.0)
    out, alpha = warp(img, src, dst, filter="bicubic")
    np.testing.assert_array_equal(alpha, 1.0)
    one = Camera.from_spec("perspective:fov=90", (32, 32), yaw=10.0 + 90.0)  # tile 1: yaw 360*1/4
    np.testing.assert_array_equal(out[:32, 32:], warp(img, src, one, filter="bicubic")[0])


@pytest.mark.parametrize("antialias", [False, True])
def test_bands_and_cache_do_not_change_the_result(antialias):
    img, src = pano(256, 128)
    dst = Camera.from_spec("fisheye:fov=200", (96, 80), pitch=30)
    ref = warp(img, src, dst, samples=4, antialias=antialias)
    for band_points in (1, 997, 50_000):
        got = warp(img, src, dst, samples=4, antialias=antialias, band_points=band_points)
        np.testing.assert_array_equal(got[0], ref[0])
        np.testing.assert_array_equal(got[1], ref[1])
    plan = WarpPlan(src, dst, samples=4, antialias=antialias, cache=True, band_points=3000)
    for _ in range(2):
        got = plan.run(img)
        np.testing.assert_array_equal(got[0], ref[0])
    assert plan.map_bytes >= 96 * 80 * 4 * 9  # x, y float32 and a validity byte per sample, all kept


def test_jittered_samples_are_deterministic_per_seed():
    img, src = pano()
    dst = Camera.from_spec("fisheye", (32, 32))
    a = warp(img, src, dst, samples=4, seed=3)[0]
    np.testing.assert_array_equal(a, warp(img, src, dst, samples=4, seed=3, band_points=100)[0])
    assert not np.array_equal(a, warp(img, src, dst, samples=4, seed=4)[0])


POSES = st.tuples(st.floats(-180, 180), st.floats(-90, 90), st.floats(-180, 180))


@settings(max_examples=25, deadline=None)
@given(model=st.sampled_from([m if m != "lensfun" else "lensfun:lens=Samyang 8mm f/3.5 Fish-Eye CS"
                               for m in sorted(REGISTRY)]), pose=POSES, src_model=st.sampled_from(["equirect", "fisheye"]))
def test_lattice_map_matches_the_exact_map(model, pose, src_model):
    """The interpolated map agrees with the exact lens maths to 1/100 px and has the same validity."""
    src = Camera.from_spec(src_model if src_model == "equirect" else "fisheye:fov=270", (512, 256))
    dst = Camera(make_lens(model, (192, 128)), Pose.from_ypr(*pose))
    m = Mapper(src, dst)
    band = m.map_band(0, 128, sample_pattern(4))
    pts = dst.pixel_grid(samples=4)
    xy, v = exact_map(src, dst, pts)
    # validity may differ only for samples within a hair of a validity edge (none in practice)
    assert np.count_nonzero(band.valid != v) <= 2
    both = band.valid & v
    dx = band.xs[both] - (xy[..., 0][both] - 0.5)
    if src_model == "equirect":
        dx -= 512 * np.round(dx / 512)  # the same point across the seam
        # judged on the sphere: toward a pole the columns crowd together, cos(latitude) pixels apart
        dx *= np.cos(np.radians(90.0 - 180.0 * xy[..., 1][both] / 256))
    dy = band.ys[both] - (xy[..., 1][both] - 0.5)
    # checked to 2e-3 px at four points per cell; measured max ~1e-2 near singular points (a pole at
    # 2 px); float32 storage adds 3e-5
    assert np.abs(dx).max(initial=0) < 0.02 and np.abs(dy).max(initial=0) < 0.02


def test_antialias_beats_single_tap_on_fine_detail():
    # a fine checkerboard (2 px squares) shrunk 4x: single taps alias, the footprint filter averages it
    w, h = 1024, 512
    yy, xx = np.mgrid[0:h, 0:w]
    img = (((xx // 2) + (yy // 2)) % 2).astype(np.float32)[..., None] * 2.0
    src = Camera.from_spec("equirect", (w, h))
    dst = Camera.from_spec("perspective:fov=90", (64, 64), pitch=20)
    ref = warp(img, src, dst, samples=256)[0]  # 16x16 supersampling: the box average, ~1.0
    single = np.abs(warp(img, src, dst)[0] - ref).mean()
    smooth = np.abs(warp(img, src, dst, antialias=True)[0] - ref).mean()
    # measured: single ~0.6 (aliasing), antialias ~0.01
    assert smooth < 0.1 * single and smooth < 0.05


@pytest.mark.parametrize("spec, pitch", [("fisheye:fov=180", 0.0), ("fisheye:fov=180,mapping=equisolid", 60.0),
                                         ("perspective:fov=90", 80.0)])
def test_lattice_error_everywhere_within_the_stated_bound(spec, pitch):
    # Every pixel of a verified lattice cell, not just its four check points (checked to 0.002 px):
    # measured 0.0020-0.0029 px here; 0.005 px leaves room for float32 storage (3e-5 at 2048 px) and
    # for other poses, and stays far below what a filter could show.
    src = Camera.from_spec("equirect", (2048, 1024))
    dst = Camera.from_spec(spec, (512, 512), pitch=pitch)
    m = Mapper(src, dst)
    assert m.lattice_fraction > 0.5  # the lattice serves most of the image
    band = m.map_band(0, 512, sample_pattern(1))
    xy, v = exact_map(src, dst, dst.pixel_grid(samples=1))
    assert np.array_equal(band.valid, v)
    dx = band.xs - (xy[..., 0] - 0.5)
    dx -= 2048 * np.round(dx / 2048)
    dx *= np.cos(np.radians(90.0 - 180.0 * xy[..., 1] / 1024))  # judged on the sphere, as the checks are
    dy = band.ys - (xy[..., 1] - 0.5)
    assert np.abs(dx[v]).max() <= 0.005 and np.abs(dy[v]).max() <= 0.005


@pytest.mark.parametrize("channels", [1, 3, 4])
@pytest.mark.parametrize("spec", ["fisheye:fov=200", "equirect", "perspective:fov=120"])
def test_a_cached_single_tap_plan_gives_the_one_shot_bits(channels, spec):
    # a cached one-sample bilinear plan keeps its map as taps (lenslab.warp.taps): offsets and weights made
    # once, the pixels whose taps cross the seam, the poles or the border through the folding sampler
    from lenslab.warp.taps import TapBand

    img, src = pano(256, 128)
    img = np.concatenate([img] * 2, axis=-1)[..., :channels]
    dst = Camera.from_spec(spec, (96, 80), pitch=60, yaw=175)  # across the seam and near a pole
    ref = warp(img, src, dst)
    plan = WarpPlan(src, dst, cache=True, band_points=2000)
    for _ in range(2):
        got = plan.run(img)
        np.testing.assert_array_equal(got[0], ref[0])
        np.testing.assert_array_equal(got[1], ref[1])
    assert all(isinstance(b, TapBand) for b in plan._bands)
    assert sum(len(b.fold_idx) for b in plan._bands) > 0  # some pixels did cross an edge
    assert plan.map_bytes >= 96 * 80 * 12
    assert all(b.xs.shape[2] == 1 for b in plan.bands())  # the maps themselves, computed again
