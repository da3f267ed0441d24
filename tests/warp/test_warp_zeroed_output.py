"""A warp into a fresh output leaves the pixels without a source alone: ``np.zeros`` gives pages the system zeroes when
first touched, so the single-sample bilinear sampler (``bilinear1(..., zeroed=True)``) writes only the samples that
land on the source, and the pages of the panorama a photo leaves unseen are never touched (the one-shot photo case of
``lenslab bench warp``). An output that holds other values (a clip's reused frame, scratch rows) is still written in
full.

Values from outside the code under test: the photo is a linear ramp ``v = a x + b y + c`` over its index
coordinates, whose bilinear interpolation is the ramp itself, so each output pixel of an equirect panorama must hold
the ramp at the pixel where the pinhole photo sees that pixel's ray: the latitude/longitude definition (v360's
``equirect``) and the pinhole projection ``x = W/2 (1 + (dx/dz) / tan(fov/2))``, ``y = H/2 (1 - (dy/dz) /
(tan(fov/2) H/W))``, transcribed here in float64. Tolerance: the map lattice's 2e-3 source pixels (LATTICE_TOL) times
the ramp's slope, plus float32's rounding of values up to 2600 (2.4e-4).
"""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.lenses import Camera
from lenslab.warp import warp
from lenslab.warp.engine import WarpPlan
from lenslab.warp.filters import sample
from lenslab.warp.kernels import native
from lenslab.warp.kernels import reference as ref
from lenslab.warp.seam import Border

K = native.kernels()
W, H, FOV = 400, 300, 70.0
A, B, C = 1.5, -2.25, 300.0  # the ramp: v = A x + B y + C at index coordinates (x, y)
OW, OH = 720, 360


def ramp_photo() -> np.ndarray:
    y, x = np.mgrid[0:H, 0:W].astype(np.float64)
    v = A * x + B * y + C
    return np.ascontiguousarray(np.stack([v, 2.0 * v, -v], -1), dtype=np.float32)


def expected():
    """Per output pixel centre: whether the photo sees its ray (well inside the frame, well outside it, or
    near its edge: None) and the ramp there."""
    j, i = np.mgrid[0:OH, 0:OW].astype(np.float64)
    lon = np.radians(-180.0 + (i + 0.5) / OW * 360.0)
    lat = np.radians(90.0 - (j + 0.5) / OH * 180.0)
    dx, dy, dz = np.cos(lat) * np.sin(lon), np.sin(lat), np.cos(lat) * np.cos(lon)
    t = np.tan(np.radians(FOV) / 2.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        px = W / 2.0 * (1.0 + dx / dz / t)
        py = H / 2.0 * (1.0 - dy / dz / (t * H / W))
    inside = (dz > 0) & (px > 1.0) & (px < W - 1.0) & (py > 1.0) & (py < H - 1.0)
    outside = (dz <= 0) | (px < -0.01) | (px > W + 0.01) | (py < -0.01) | (py > H + 0.01)
    v = A * (px - 0.5) + B * (py - 0.5) + C
    return inside, outside, v


@pytest.mark.parametrize("samples_at_once", [1 << 18, 5000])
def test_a_photo_in_a_fresh_panorama_is_the_ramp_where_seen_and_zero_elsewhere(samples_at_once):
    out, alpha = warp(ramp_photo(), Camera.from_spec(f"perspective:fov={FOV}", (W, H)),
                      Camera.from_spec("equirect", (OW, OH)), band_points=samples_at_once)
    inside, outside, v = expected()
    assert inside.sum() > 12000 and outside.sum() > 200000
    tol = 2e-3 * np.hypot(A, B) * 2.0 + 2.4e-4 * 2.0  # (the second channel's slope is twice the ramp's)
    np.testing.assert_allclose(out[inside], np.stack([v, 2.0 * v, -v], -1)[inside], rtol=0, atol=tol)
    assert (alpha[inside] == 1.0).all()
    assert not out[outside].any() and not alpha[outside].any()
    assert not np.signbit(out[outside]).any()  # +0, as written before


def test_a_reused_output_is_still_written_in_full():
    """A plan drawing into arrays it is given (a clip's frames) cannot count on zeros there."""
    src, dst = Camera.from_spec(f"perspective:fov={FOV}", (W, H)), Camera.from_spec("equirect", (OW, OH))
    plan = WarpPlan(src, dst)
    into = (np.full((OH, OW, 3), np.nan, np.float32), np.full((OH, OW), 7.0, np.float32))
    out, alpha = plan.run(ramp_photo(), into=into)
    assert out is into[0]
    _, outside, _ = expected()
    assert not out[outside].any() and not alpha[outside].any()
    fresh, fresh_alpha = plan.run(ramp_photo())
    np.testing.assert_array_equal(out, fresh)
    np.testing.assert_array_equal(alpha, fresh_alpha)


@pytest.mark.parametrize("nc", [1, 3, 4, 5])
def test_the_sampler_leaves_samples_without_a_source_alone_when_told_the_output_is_zeroed(nc):
    rng = np.random.default_rng(nc)
    h, w, n = 9, 13, 3000
    src = rng.uniform(-2.0, 2.0, (h, w, nc)).astype(np.float32)
    xs = rng.uniform(-1.0, w, n).astype(np.float32)
    ys = rng.uniform(-1.0, h, n).astype(np.float32)
    valid = rng.uniform(size=n) < 0.3
    valid[100:2000] = False  # a long run without a source, as across a panorama a photo does not cover
    flags = Border(True, True, True).flags
    want, want_alpha = ref.bilinear1(src, xs, ys, valid, flags)
    tol = 4 * np.finfo(np.float32).eps * 2.0  # the reference rounds each lerp, the kernel may fuse them (4 ulp)
    for zeroed in (False, True):
        out, alpha = np.full((n, nc), 7.0, np.float32), np.full(n, 7.0, np.float32)
        said = K.bilinear1(src.reshape(-1), w, h, nc, xs, ys, valid, *flags, out, alpha, zeroed=zeroed)
        assert said == 2  # covered, all finite
        np.testing.assert_allclose(out[valid], want[valid], rtol=0, atol=tol)
        np.testing.assert_array_equal(alpha[valid], 1.0)
        if zeroed:  # untouched
            assert (out[~valid] == 7.0).all() and (alpha[~valid] == 7.0).all()
            np.testing.assert_array_equal(out[valid], kept[valid])  # the same values either way
        else:
            kept = out.copy()
            assert not out[~valid].any() and not np.signbit(out[~valid]).any()
            np.testing.assert_array_equal(alpha, want_alpha)
    # through filters.sample, the same
    out, alpha = np.full((1, n, nc), 7.0, np.float32), np.full((1, n), 7.0, np.float32)
    sample(src, xs.reshape(1, n, 1), ys.reshape(1, n, 1), valid.reshape(1, n, 1), Border(True, True, True),
           "bilinear", out, alpha, zeroed=True)
    assert (out[0, ~valid] == 7.0).all()
    np.testing.assert_array_equal(out[0, valid], kept[valid])
