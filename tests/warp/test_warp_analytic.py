"""Warps against the analytic truth: a panorama made from a function of direction, warped into every
lens model, compared with the same function evaluated at the output rays."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.lenses import REGISTRY, Camera, make_lens
from lenslab.warp import warp

SAMPLES = 4  # 2x2 strata centres per output pixel, both in the warp and in the truth


def smooth_scene(d: np.ndarray) -> np.ndarray:
    """A smooth function of direction (polynomials in the components: no seam, no pole singularity)."""
    x, y, z = d[..., 0], d[..., 1], d[..., 2]
    a = 1.0 + 0.5 * x + 0.25 * y + 0.3 * z * z + 0.2 * x * y
    return np.stack([a, 2.0 - x * z + 0.4 * y * y * y, 1.0 + np.sin(3.0 * x) * np.cos(2.0 * y)], axis=-1)


def scene(d: np.ndarray) -> np.ndarray:
    """An HDR function of unit direction: smooth polynomial plus sharp-edged disks (one across a pole,
    one across the equirect seam, one small and bright like a sun). Shape (..., 3) float64."""
    x, y, z = d[..., 0], d[..., 1], d[..., 2]
    smooth = 1.0 + 0.5 * x + 0.25 * y + 0.3 * z * z + 0.2 * x * y
    def disk(center, radius_deg):
        c = np.asarray(center, dtype=np.float64)
        c = c / np.linalg.norm(c)
        return (d @ c) > np.cos(np.radians(radius_deg))
    pole = disk([0.2, 1.0, 0.1], 25.0)  # covers the north pole, off-centre
    seam = disk([0.1, -0.2, -1.0], 20.0)  # straddles the seam (behind, -z)
    sun = disk([0.5, 0.3, 0.8], 4.0)
    r = smooth + 2.0 * pole + 1.5 * seam + 20.0 * sun
    g = smooth + 1.0 * pole - 0.5 * seam + 18.0 * sun
    b = smooth * 0.5 + 3.0 * seam
    return np.stack([r, g, b], axis=-1)


def panorama(width: int, fn=scene) -> tuple[np.ndarray, Camera]:
    """The function point-sampled at the pixel centres of a full equirect panorama."""
    cam = Camera.from_spec("equirect", (width, width // 2))
    _, d, _ = cam.rays(samples=1, seed=None)
    return fn(d[:, :, 0]).astype(np.float32), cam


def truth(dst: Camera, fn=scene) -> tuple[np.ndarray, np.ndarray]:
    """The function averaged over each pixel's strata (premultiplied by coverage) and the coverage.

    A lens with per-channel optics takes channel c along its channel lens c's rays (coverage from G),
    and the result is dimmed by its falloff at each pixel centre (the engine's documented rule)."""
    _, d, v = dst.rays(samples=SAMPLES, seed=None)
    f = np.where(v[..., None], fn(d), 0.0)
    channels = dst.lens.channel_lenses()
    if channels is not None:
        for c, lens in enumerate(channels):
            _, dc, vc = Camera(lens, dst.pose).rays(samples=SAMPLES, seed=None)
            f[..., c] = np.where(vc, fn(dc)[..., c], 0.0)
    out = f.mean(axis=2)
    y, x = np.mgrid[0:dst.height, 0:dst.width] + 0.5
    fall = dst.lens.falloff(np.stack([x, y], axis=-1))
    if fall is not None:
        out *= fall[..., None]
    return out, v.mean(axis=2)


def dst_camera(model: str) -> Camera:
    lens = make_lens(model, (96, 64))
    return Camera(lens, Camera.from_spec("equirect", (2, 1), yaw=25, pitch=10, roll=5).pose)


#: every model; a lensfun profile needs a lens named (a full-frame fisheye, distortion from the database)
MODELS = [m if m != "lensfun" else "lensfun:lens=Canon EF 8-15mm f/4L Fisheye USM,crop=1,focal=10"
          for m in sorted(REGISTRY)]


# largest mean error (per pixel and channel, values ~1..25) measured at 512 px over every model, times ~2.5:
# the sharp disks dominate, and their misplaced area shrinks with the source pixel size. A half-pixel
# shift or a wrong seam/pole costs several times more.
BOUND_512 = {"nearest": 0.030, "bilinear": 0.030, "bicubic": 0.032, "lanczos": 0.036}


@pytest.mark.parametrize("model", MODELS)
def test_every_model_converges_to_the_truth(model):
    dst = dst_camera(model)
    ref, cover = truth(dst)
    errors = {}
    for width in (128, 512):
        img, src = panorama(width)
        for filt in BOUND_512:
            out, alpha = warp(img, src, dst, filter=filt, samples=SAMPLES)
            assert out.dtype == np.float32 and alpha.dtype == np.float32
            assert np.isfinite(out).all()
            # an equirect source sees every direction: coverage is exactly the output lens's own
            np.testing.assert_array_equal(alpha, cover.astype(np.float32))
            assert np.all(out[alpha == 0] == 0)
            full = cover == 1
            assert full.any()
            errors[filt, width] = float(np.abs(out - ref)[full].mean())
    for filt, bound in BOUND_512.items():
        lo, hi = errors[filt, 128], errors[filt, 512]
        # 4x the source resolution: measured 3.5-5x smaller; at least halved
        assert hi < 0.5 * lo, (model, filt, lo, hi)
        assert hi < bound, (model, filt, hi)


@pytest.mark.parametrize("model", ["fisheye", "perspective", "equirect"])
def test_smooth_scene_error_orders(model):
    """On a smooth scene the filters show their textbook orders: nearest O(h), bilinear O(h^2),
    Catmull-Rom better still. Lanczos-3 does not reproduce linear functions exactly (its normalised
    weights leave an O(h) term with a small constant): far better than nearest, not better than bilinear
    on smooth content (measured 2x worse at 512 px); its strength is sharpness, not smooth gradients."""
    dst = dst_camera(model)
    ref, cover = truth(dst, smooth_scene)
    full = cover == 1
    err = {}
    for width in (128, 512):
        img, src = panorama(width, smooth_scene)
        for filt in ("nearest", "bilinear", "bicubic", "lanczos"):
            out, _ = warp(img, src, dst, filter=filt, samples=SAMPLES)
            err[filt, width] = float(np.abs(out - ref)[full].max())
    # 4x finer: O(h) gives 4x, O(h^2) 16x; measured nearest 4.4-5.3x, bilinear 15.4-16.2x, Lanczos ~4x,
    # Catmull-Rom > 100x; the bounds allow for the constants' drift
    assert err["nearest", 128] / err["nearest", 512] > 3.0
    assert err["bilinear", 128] / err["bilinear", 512] > 12.0
    assert err["lanczos", 128] / err["lanczos", 512] > 3.0
    assert err["bicubic", 128] / err["bicubic", 512] > 20.0
    for width in (128, 512):
        assert err["bilinear", width] < err["nearest", width] / 4
        assert err["bicubic", width] < err["bilinear", width] / 4
        assert err["lanczos", width] < err["nearest", width] / 4
