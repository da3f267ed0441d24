"""The footprint sides of one-sample pixels (``neighbour_secants``, eight pixels at a time where the CPU has AVX2)
and the far footprints it marks for the pyramid (``coarse``): against the central differences of the equirect and
perspective formulas transcribed here in float64, against the NumPy reference, and the marks against the float64
test the pyramid's level_rows makes."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.lenses import Camera, Pose
from lenslab.warp import warp
from lenslab.warp.antialias import neighbour_secants
from lenslab.warp.engine import WarpPlan
from lenslab.warp.kernels import reference as ref
from lenslab.warp.kernels.dispatch import set_threads
from lenslab.warp.kernels.pyramid_reference import far_samples
from lenslab.warp.pyramid import MAX_TAPS

SW, SH = 4096, 2048  # the source panorama


def _formula_map(w, h, fov, yaw, pitch, px, py):
    """Source index coordinates of output positions (px, py) (continuous pixels) of a perspective view (``fov``
    degrees, turned by yaw then pitch) of an equirect panorama, from CONVENTIONS.md's formulas in float64."""
    t = np.tan(np.radians(fov) / 2)
    u, v = np.broadcast_arrays(2 * px / w - 1, (1 - 2 * py / h) * h / w)
    d = np.stack([u * t, v * t, np.ones_like(u)], axis=-1)
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    p, y = np.radians(pitch), np.radians(yaw)
    rx = np.array([[1, 0, 0], [0, np.cos(p), np.sin(p)], [0, -np.sin(p), np.cos(p)]])  # pitch up about +x
    ry = np.array([[np.cos(y), 0, np.sin(y)], [0, 1, 0], [-np.sin(y), 0, np.cos(y)]])  # yaw right about +y
    d = d @ (ry @ rx).T
    phi, theta = np.arctan2(d[..., 0], d[..., 2]), np.arcsin(np.clip(d[..., 1], -1, 1))
    return (phi / np.pi + 1) * SW / 2 - 0.5, (1 - theta / (np.pi / 2)) * SH / 2 - 0.5


@pytest.mark.parametrize("yaw, pitch", [(0.0, 0.0), (180.0, 20.0), (30.0, 70.0)])  # the seam; near the pole
def test_footprints_are_the_central_differences_of_the_lens_formulas(yaw, pitch):
    w, h, fov = 160, 96, 100.0
    src = Camera.from_spec("equirect", (SW, SH))
    dst = Camera(Camera.from_spec(f"perspective:fov={fov:g}", (w, h)).lens, Pose.from_ypr(yaw, pitch, 0.0))
    plan = WarpPlan(src, dst, antialias=True, exact_map=True)
    bands = list(plan.bands())
    foot = np.concatenate([b.foot[:, :, 0] for b in bands])  # (h, w, 4)
    coarse = np.concatenate([b.coarse + b.r0 * w for b in bands])
    x, y = np.arange(w) + 0.5, np.arange(h) + 0.5
    cx = lambda dx: _formula_map(w, h, fov, yaw, pitch, x[None, :] + dx, y[:, None])  # noqa: E731
    cy = lambda dy: _formula_map(w, h, fov, yaw, pitch, x[None, :], y[:, None] + dy)  # noqa: E731
    (xr, yr), (xl, yl), (xd, yd), (xu, yu) = cx(1.0), cx(-1.0), cy(1.0), cy(-1.0)
    ax, bx = (((v + SW / 2) % SW - SW / 2) / 2 for v in (xr - xl, xd - xu))  # across the seam: the short way
    want = np.stack([ax, (yr - yl) / 2, bx, (yd - yu) / 2], axis=-1)
    inner = (slice(1, -1), slice(1, -1))
    # the map is held as float32 index coordinates: each of the two positions of a difference is off by at most
    # half a float32 ulp at 4096 (2^-12), so a halved difference by 2^-12, and the side is rounded to float32
    err = np.abs(foot[inner] - want[inner])
    assert err.max() <= 2.0**-12 + np.spacing(np.abs(want[inner]).astype(np.float32)).max()
    # every footprint the pyramid's level_rows sends beyond level 0 is marked, the others only within a float32
    # rounding of MAX_TAPS
    valid = np.concatenate([b.valid[:, :, 0] & ~b.edge[:, :, 0] for b in bands])
    need = far_samples(foot, valid, MAX_TAPS)
    assert np.isin(need, coarse).all()
    assert len(need) > (1000 if pitch == 70.0 else 0)  # the view near the pole reads coarser levels most
    f = foot.reshape(-1, 4).astype(np.float64)[coarse]
    assert (np.maximum(f[:, 0] ** 2 + f[:, 1] ** 2, f[:, 2] ** 2 + f[:, 3] ** 2) > MAX_TAPS ** 2 * (1 - 2e-6)).all()
    assert np.array_equal(coarse, np.unique(coarse))  # in order, each once


@pytest.mark.parametrize("wrap", [0.0, 64.0, 4096.0])
def test_eight_at_a_time_match_the_numpy_reference(wrap):
    """Wide rows of one validity (the vector path) beside scattered invalid pixels and a disc's rim (the scalar
    path), across a seam: the reference's bits. The seam's turns are whole, so a fused multiply-add in unwrapping
    rounds as the reference does."""
    rng = np.random.default_rng(int(wrap))
    nrows, w, top, h = 40, 203, 1, 38
    rows, cols = np.mgrid[0:nrows, 0:w]
    xs = (cols * 0.37 + rows * 0.11 + rng.uniform(0, 0.2, (nrows, w))).astype(np.float32)
    if wrap:
        xs = (xs * (wrap / 40.0)) % np.float32(wrap)  # every row crosses the seam
    ys = (rows * 9.5 + cols * 0.02 + rng.uniform(0, 0.2, (nrows, w))).astype(np.float32)
    vs = (rows - 20) ** 2 + (cols - 100) ** 2 < 90 ** 2  # a disc
    vs[rng.uniform(size=vs.shape) < 0.002] = False
    foot = np.full((h, w, 1, 4), np.nan, np.float32)
    edge = np.zeros((h, w, 1), bool)
    coarse = neighbour_secants(xs, ys, vs, top, wrap, None, foot, edge, far=4.0)
    want, want_edge = ref.neighbour_secants(xs, ys, vs, top, h, wrap, None)
    np.testing.assert_array_equal(edge[..., 0], want_edge)
    np.testing.assert_array_equal(foot[:, :, 0], want)
    need = far_samples(want, vs[top:top + h], 4.0)
    assert len(need) > 100 and np.isin(need, coarse).all()
    assert np.array_equal(coarse, np.unique(coarse)) and vs[top:top + h].reshape(-1)[coarse].all()


def test_antialias_gives_the_same_bits_on_one_two_and_three_threads():
    rng = np.random.default_rng(7)
    img = rng.uniform(0, 1, (256, 512, 3)).astype(np.float32)
    img[::23, ::19] = 3e4  # small bright texels
    src, dst = Camera.from_spec("equirect", (512, 256)), Camera.from_spec("fisheye:fov=190", (200, 200))
    outs = []
    try:
        for n in (1, 2, 3):
            set_threads(n)
            outs.append(warp(img, src, dst, antialias=True, band_points=4096))
    finally:
        set_threads(None)
    for out, alpha in outs[1:]:
        np.testing.assert_array_equal(out, outs[0][0])
        np.testing.assert_array_equal(alpha, outs[0][1])
    assert np.isfinite(outs[0][0]).all()
