"""A dual-fisheye *source* blends its two lenses across their overlap (issue: every 360 projection).

The expected values are computed here from the geometry written out in float64: the equirect output
rays of docs/conventions.md, the angle of each ray from the front (+z) and back (-z) axes, and the
smoothstep blend over the overlap band stated in docs/conventions.md (``w = clip((F - a) / (2F - pi),
0, 1)``, ``w^2 (3 - 2w)``, normalised to sum 1).
"""

from __future__ import annotations

import numpy as np
import pytest

import lenslab
from lenslab.lenses import Camera

FOV = 200.0
F = np.radians(FOV / 2)
OUT_W, OUT_H = 128, 64
SRC_W, SRC_H = 512, 256


def equirect_rays(w: int, h: int) -> np.ndarray:
    """Unit rays of an equirect's pixel centres (docs/conventions.md), float64 (h, w, 3)."""
    x = (np.arange(w) + 0.5)[None, :]
    y = (np.arange(h) + 0.5)[:, None]
    phi = (2 * x / w - 1) * np.pi
    theta = (1 - 2 * y / h) * np.pi / 2
    return np.stack(np.broadcast_arrays(np.cos(theta) * np.sin(phi), np.sin(theta), np.cos(theta) * np.cos(phi)), -1)


def smoothstep_weight(a: np.ndarray) -> np.ndarray:
    w = np.clip((F - a) / (2 * F - np.pi), 0.0, 1.0)
    return w * w * (3 - 2 * w)


def front_is_right() -> bool:
    lens = Camera.from_spec(f"dual-fisheye:fov={FOV:g}", (SRC_W, SRC_H)).lens
    xy, ok = lens.dir_to_pixel(np.array([0.0, 0.0, 1.0]))
    assert ok
    return bool(xy[0] > SRC_W / 2)


def test_overlap_is_the_smoothstep_mix_of_the_two_lenses():
    # front lens sees radiance 2, back lens 1: every output pixel is their blend by the stated weights;
    # nearest sampling reads exactly the constant of the half it lands in, so the only rounding is float32
    front, back = 2.0, 1.0
    img = np.empty((SRC_H, SRC_W, 3), np.float32)
    right = front_is_right()
    img[:, SRC_W // 2:] = front if right else back
    img[:, :SRC_W // 2] = back if right else front
    src = Camera.from_spec(f"dual-fisheye:fov={FOV:g}", (SRC_W, SRC_H))
    dst = Camera.from_spec("equirect", (OUT_W, OUT_H))
    out, alpha = lenslab.warp(img, src, dst, filter="nearest")

    d = equirect_rays(OUT_W, OUT_H)
    a_front = np.arccos(np.clip(d[..., 2], -1, 1))
    w_f, w_b = smoothstep_weight(a_front), smoothstep_weight(np.pi - a_front)
    expected = (front * w_f + back * w_b) / (w_f + w_b)
    assert np.all(alpha == 1.0)
    np.testing.assert_allclose(out[..., 0], expected, rtol=0, atol=2e-6)  # float32 sums of two products
    band = (w_f > 0) & (w_b > 0)
    assert band.sum() > OUT_W * 4  # the overlap band really is exercised (about 20 degrees of 180)
    assert np.all(out[..., 0][~band] == np.where(w_f[~band] > 0, front, back))  # one lens outside it
    # across the band the output passes through every intermediate value, not a step
    assert np.unique(np.round(out[..., 0][band], 3)).size > 20


def dual_fisheye_image(f) -> np.ndarray:
    """A dual-fisheye frame whose pixel centres hold ``f`` of their ray: the equidistant mapping
    ``a = r F`` of docs/conventions.md written out, continued past each circle's rim so that bilinear taps
    there read the same smooth function."""
    right = front_is_right()
    half = SRC_W // 2
    x = (np.arange(SRC_W) + 0.5)[None, :]
    y = (np.arange(SRC_H) + 0.5)[:, None]
    x0 = np.where(x >= half, half, 0)
    u = 2 * (x - x0) / half - 1
    v = (1 - 2 * y / SRC_H) * (SRC_H / half)
    u, v = np.broadcast_arrays(u, v)
    r = np.hypot(u, v)
    a = r * F
    s = np.where(r > 0, np.sin(a) / np.where(r > 0, r, 1), F)
    local = np.stack([s * u, s * v, np.cos(a)], -1)
    is_front = (x >= half) == right
    is_front = np.broadcast_to(is_front, u.shape)
    d = np.where(is_front[..., None], local, local * np.array([-1.0, 1.0, -1.0]))  # back lens: half a turn about +y
    return f(d).astype(np.float32)


def smooth(d: np.ndarray) -> np.ndarray:
    return np.stack([1 + 0.5 * d[..., 0], 1 + 0.3 * d[..., 1], 1 + 0.4 * d[..., 2]], -1)


@pytest.mark.parametrize("filter_name", ["bilinear", "bicubic"])
def test_a_seamless_scene_stays_seamless_through_the_overlap(filter_name):
    img = dual_fisheye_image(smooth)
    src = Camera.from_spec(f"dual-fisheye:fov={FOV:g}", (SRC_W, SRC_H))
    dst = Camera.from_spec("equirect", (OUT_W, OUT_H))
    out, alpha = lenslab.warp(img, src, dst, filter=filter_name)
    expected = smooth(equirect_rays(OUT_W, OUT_H))
    assert np.all(alpha == 1.0)
    # interpolating a function linear in the ray over 0.78-degree source pixels: the error is the
    # mapping's curvature times h^2/8, about 3e-5; 3e-4 leaves room and still catches a wrong lens or half
    np.testing.assert_allclose(out, expected, rtol=0, atol=3e-4)


def test_antialias_on_a_dual_fisheye_source_still_blends():
    # the footprint prefilter reads one place per direction, so antialias on a two-view source
    # supersamples the blended views (4x4): a seamless scene stays seamless, within the same bound
    img = dual_fisheye_image(smooth)
    src = Camera.from_spec(f"dual-fisheye:fov={FOV:g}", (SRC_W, SRC_H))
    dst = Camera.from_spec("equirect", (OUT_W, OUT_H))
    out, alpha = lenslab.warp(img, src, dst, antialias=True)
    np.testing.assert_allclose(alpha, 1.0, rtol=0, atol=1e-6)  # float32 sum of 16 strata of weights 1/16
    # the 4x4 strata average the linear function over each output pixel: against the pixel-centre value
    # the difference is the function's curvature over one output pixel (2.8 degrees), about 1e-4
    np.testing.assert_allclose(out, smooth(equirect_rays(OUT_W, OUT_H)), rtol=0, atol=1e-3)
    flat = np.empty((SRC_H, SRC_W, 3), np.float32)
    right = front_is_right()
    flat[:, SRC_W // 2:] = 2.0 if right else 1.0
    flat[:, :SRC_W // 2] = 1.0 if right else 2.0
    out, _ = lenslab.warp(flat, src, dst, antialias=True)
    a_front = np.arccos(np.clip(equirect_rays(OUT_W, OUT_H)[..., 2], -1, 1))
    band = (smoothstep_weight(a_front) > 0.05) & (smoothstep_weight(np.pi - a_front) > 0.05)
    assert np.all((out[..., 0][band] > 1.02) & (out[..., 0][band] < 1.98))  # mixed, not one lens
