"""A one-shot warp maps its bands into scratch arrays kept between bands and warps, and its lenses' compiled
kernels take whole blocks of four directions: the output is the same bits on one thread or two, with bands of
any height (a block of four straddles band edges differently), after other warps have left other values in the
scratch, and the same as a plan that keeps its maps; and the map the lattice leaves to the exact kernels still
lands where the float64 formulas of the two lenses, transcribed here, put it."""

from __future__ import annotations

import math

import numpy as np

from lenslab.lenses import Camera
from lenslab.warp import WarpPlan, exact_map, warp
from lenslab.warp.kernels.dispatch import set_threads

RNG = np.random.default_rng(11)
SRC = RNG.random((256, 512, 3), dtype=np.float32)


def _warp(spec, threads, band_points, size=(200, 200)):
    set_threads(threads)
    try:
        return warp(SRC, Camera.from_spec("equirect", (512, 256)), Camera.from_spec(spec, size),
                    band_points=band_points)
    finally:
        set_threads(None)


def test_same_bits_on_any_thread_count_band_height_and_after_other_warps():
    for spec in ("fisheye:fov=180", "fisheye:fov=360", "fisheye:fov=200,mapping=equisolid"):
        ref, ref_alpha = _warp(spec, 1, 1 << 18)
        _warp("perspective:fov=90", 2, 999, (123, 77))  # leaves other values in the scratch arrays
        for threads, band_points in ((2, 1 << 18), (2, 3 * 200 + 1), (1, 7 * 200 + 3)):
            out, alpha = _warp(spec, threads, band_points)
            np.testing.assert_array_equal(out, ref, err_msg=f"{spec} {threads} {band_points}")
            np.testing.assert_array_equal(alpha, ref_alpha)
        plan = WarpPlan(Camera.from_spec("equirect", (512, 256)), Camera.from_spec(spec, (200, 200)), cache=True)
        for _ in range(2):
            out, alpha = plan.run(SRC)
            np.testing.assert_array_equal(out, ref)
            np.testing.assert_array_equal(alpha, ref_alpha)


def test_exact_map_matches_the_transcribed_formulas():
    """Equidistant fisheye r = f theta (f = (W/2) / (fov/2)) into an equirect x = (phi/pi + 1) W/2,
    y = (1/2 - lat/pi) H, phi = atan2(dx, dz), lat = asin(dy); 1e-9 px (a few ulps of atan2 at 4096 px)."""
    w, fov = 1000, 180.0
    src, dst = Camera.from_spec("equirect", (4096, 2048)), Camera.from_spec(f"fisheye:fov={fov:g}", (w, w))
    pts = np.stack([RNG.uniform(0, w, 5000), RNG.uniform(0, w, 5000)], -1)
    dx, dy = pts[:, 0] - w / 2, w / 2 - pts[:, 1]
    r = np.hypot(dx, dy)
    inside = r <= w / 2
    theta = r / ((w / 2) / math.radians(fov / 2))
    d = np.stack([np.sin(theta) * dx / np.where(r > 0, r, 1), np.sin(theta) * dy / np.where(r > 0, r, 1),
                  np.cos(theta)], -1)
    want = np.stack([(np.arctan2(d[:, 0], d[:, 2]) / np.pi + 1) * 2048,
                     (0.5 - np.arcsin(np.clip(d[:, 1], -1, 1)) / np.pi) * 2048], -1)
    xy, ok = exact_map(src, dst, pts)
    np.testing.assert_array_equal(ok, inside)
    np.testing.assert_allclose(xy[ok], want[ok], rtol=0, atol=1e-9)
