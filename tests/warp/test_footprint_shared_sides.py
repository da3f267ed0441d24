"""The footprint filter on rows of pixels: neighbours share the side between them, and a run of pixels shares one
window of the source (``src/native/footprint_setup.h``, ``src/native/footprint_chunks.h``; NumPy reference
:func:`lenslab.warp.kernels.footprint_reference.footprint`).

Outside values: on an affine map every footprint is the pixel's exact preimage, a parallelogram whose sides
coincide with its neighbours', and a source whose texels sample f = c0 + c1 x + c2 y + c3 x y is reconstructed
bilinearly as f itself. Its mean over the parallelogram c + s a + t b (s, t in [-1/2, 1/2]) is
f(c) + c3 (ax ay + bx by) / 12 (the mean of s^2 and of t^2 is 1/12, of s t and of s and t zero), transcribed here
in float64. On a curved map the quadrilaterals are held to the NumPy reference, and to a 64x64 supersample of the
quadrilateral that reference builds (the float64 polygon and bilinear formulas written out in this test).
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from lenslab import cxx_kernels as K
from lenslab.lenses import Camera
from lenslab.warp.engine import WarpPlan
from lenslab.warp.kernels import footprint_reference as fref
from lenslab.warp.pyramid import MAX_TAPS, pyramid
from lenslab.warp.seam import Border

EPS32 = float(np.finfo(np.float32).eps)
PANO = Border(True, True, True)
COEF = np.array([[2.0, 0.05, 0.1, 0.003], [0.5, -0.004, 0.02, 0.0007], [7.0, 0.01, -0.03, -0.0002]])


def _bilinear_source(h, w):
    j, i = np.mgrid[0:h, 0:w].astype(np.float64)
    return np.stack([c[0] + c[1] * i + c[2] * j + c[3] * i * j for c in COEF], axis=-1).astype(np.float32)


def _run(pyr, xs, ys, valid, foot, border=PANO):
    out = np.empty(xs.shape[:2] + (pyr.channels,), np.float32)
    alpha = np.empty(xs.shape[:2], np.float32)
    K.footprint(pyr.level0, pyr.rest, pyr.shapes, pyr.offsets, xs, ys, valid, foot, *border.flags, MAX_TAPS,
                out, alpha)
    return out, alpha


def _affine_rows(h, w, origin, a, b):
    r, p = np.mgrid[0:h, 0:w].astype(np.float64)
    xs = origin[0] + a[0] * p + b[0] * r
    ys = origin[1] + a[1] * p + b[1] * r
    foot = np.broadcast_to(np.array([a[0], a[1], b[0], b[1]], np.float32), (h, w, 1, 4))
    return (xs[..., None].astype(np.float32), ys[..., None].astype(np.float32), np.ones((h, w, 1), bool),
            np.ascontiguousarray(foot))


@pytest.mark.parametrize("a, b", [((1.7, -0.3), (0.4, 1.9)), ((2.6, 0.0), (0.0, 2.2)), ((-1.1, 0.8), (0.9, 1.5))])
def test_affine_rows_give_the_exact_mean_of_a_bilinear_source(a, b):
    src = _bilinear_source(64, 96)
    pyr = pyramid(src, PANO)
    xs, ys, valid, foot = _affine_rows(14, 20, (30.3, 12.1), a, b)
    out, alpha = _run(pyr, xs, ys, valid, foot)
    cx, cy = xs[..., 0].astype(np.float64), ys[..., 0].astype(np.float64)
    want = np.stack([c[0] + c[1] * cx + c[2] * cy + c[3] * (cx * cy + (a[0] * a[1] + b[0] * b[1]) / 12.0)
                     for c in COEF], axis=-1)
    # float64 throughout, one float32 rounding of the result (and of the float32 source's texels: the texels of
    # f here are whole multiples of 2^-14 below 64, exact in float32, but for COEF's last column)
    np.testing.assert_allclose(out, want, rtol=8 * EPS32, atol=8 * EPS32 * np.abs(src).max())
    assert (alpha == 1.0).all()


def _lens_band(spec, yaw=0.0, size=36):
    src = Camera.from_spec("equirect", (128, 64))
    plan = WarpPlan(src, Camera.from_spec(spec, (size, size), yaw=yaw, pitch=10.0), antialias=True)
    band = next(iter(plan.bands()))
    return band.xs, band.ys, np.ascontiguousarray(band.valid & ~band.edge), band.foot


@pytest.mark.parametrize("spec, yaw", [("fisheye:fov=180", 0.0), ("swirl:amount=6", 0.0),
                                       ("perspective:fov=100", 180.0)])
def test_rows_match_the_numpy_reference(spec, yaw):
    rng = np.random.default_rng(3)
    src = rng.uniform(0.0, 1.0, (64, 128, 3)).astype(np.float32)
    src[10:12, 40:42] = 300.0  # a lamp: the shared windows' prefix sums carry it along their rows
    pyr = pyramid(src, PANO)
    xs, ys, valid, foot = _lens_band(spec, yaw)
    out, alpha = _run(pyr, xs, ys, valid, foot)
    want, want_alpha = fref.footprint(pyr, xs, ys, valid, foot, PANO.flags)
    np.testing.assert_array_equal(alpha.ravel(), want_alpha)
    # float64 sums in another order (shared windows: prefix sums from another texel; a shared side integrated
    # once), rounded once to float32: within 2 float32 ulp of the largest texel
    np.testing.assert_allclose(out.reshape(-1, 3), want, rtol=2 * EPS32, atol=2 * EPS32 * src.max())


def _shoelace_moments(vx, vy):
    """Area and the integrals of x, y and x y over a polygon (the float64 polygon-moment formulas)."""
    x1, y1 = np.roll(vx, -1), np.roll(vy, -1)
    c = vx * y1 - x1 * vy
    area = c.sum() / 2.0
    mx = ((vx + x1) * c).sum() / 6.0
    my = ((vy + y1) * c).sum() / 6.0
    mxy = ((vx * y1 + 2 * vx * vy + 2 * x1 * y1 + x1 * vy) * c).sum() / 24.0
    return area, mx, my, mxy


def test_shared_quadrilaterals_average_a_bilinear_source_exactly():
    # a curved map: the reference's quadrilaterals (sides shared) hold the exact polygon mean of f, and the kernel
    # gives it
    src = _bilinear_source(64, 128)
    pyr = pyramid(src, PANO)
    xs, ys, valid, foot = _lens_band("fisheye:fov=120")
    inner = valid & (xs > 4) & (xs < 123) & (ys > 4) & (ys < 59)  # clear of the seam and the poles
    out, _ = _run(pyr, xs, ys, inner, foot)
    levels = [pyr.source]
    r = xs.shape[0] // 2  # the middle row
    row = [fref._sample(levels, 64.0, xs[r, p, 0], ys[r, p, 0], foot[r, p, 0].astype(np.float64))
           if inner[r, p, 0] else None for p in range(xs.shape[1])]
    fref.share_sides(row, pyr.shapes[:, 1], True)
    checked = 0
    for p, smp in enumerate(row):
        if smp is None or smp["quad"] is None or smp["lev"] != 0:
            continue
        vx = np.array([smp["cx"] + v[0] for v in smp["quad"]])
        vy = np.array([smp["cy"] + v[1] for v in smp["quad"]])
        area, mx, my, mxy = _shoelace_moments(vx, vy)
        want = [c[0] + (c[1] * mx + c[2] * my + c[3] * mxy) / area for c in COEF]
        np.testing.assert_allclose(out[r, p], want, rtol=8 * EPS32, atol=8 * EPS32 * np.abs(src).max())
        checked += 1
    assert checked > 10


@settings(max_examples=25, deadline=None)
@given(st.floats(0.4, 3.0), st.floats(-0.6, 0.6), st.floats(-0.6, 0.6), st.floats(0.4, 3.0),
       st.floats(-0.02, 0.02), st.floats(1e-3, 1e4))
def test_a_constant_source_stays_that_constant(ax, ay, bx, by, bend, value):
    # normalised by the signed area of each quadrilateral: any smooth map, any constant
    src = np.full((64, 128, 3), value, np.float32)
    pyr = pyramid(src, PANO)
    xs, ys, valid, foot = _affine_rows(10, 24, (40.0, 20.0), (ax, ay), (bx, by))
    p = np.arange(24, dtype=np.float32)[None, :, None]
    ys = (ys + bend * (p - 12.0) ** 2).astype(np.float32)  # a curved row: sides no longer coincide
    foot = foot.copy()
    foot[..., 1] += (2.0 * bend * (p - 12.0)).astype(np.float32)
    out, _ = _run(pyr, xs, ys, valid, foot)
    np.testing.assert_allclose(out, value, rtol=1e-6)


def test_rows_do_not_depend_on_how_they_are_split():
    # one call for the band, or one per row, or rows of another band split: the same bits
    rng = np.random.default_rng(5)
    src = rng.uniform(0.0, 2.0, (64, 128, 3)).astype(np.float32)
    pyr = pyramid(src, PANO)
    xs, ys, valid, foot = _lens_band("fisheye:fov=180", 30.0, size=48)
    whole, _ = _run(pyr, xs, ys, valid, foot)
    for r0, r1 in ((0, 1), (1, 7), (7, xs.shape[0])):
        part, _ = _run(pyr, *(np.ascontiguousarray(a[r0:r1]) for a in (xs, ys, valid, foot)))
        np.testing.assert_array_equal(part, whole[r0:r1])


def test_a_finite_source_gives_finite_rows_beside_non_finite_positions():
    src = np.random.default_rng(6).uniform(0.0, 1e30, (64, 128, 3)).astype(np.float32)
    pyr = pyramid(src, PANO)
    xs, ys, valid, foot = _lens_band("fisheye:fov=180")
    xs = xs.copy()
    foot = foot.copy()
    xs[0, ::7] = np.nan
    xs[0, 3::11] = np.inf
    foot[0, 5::9, 0, 0] = np.nan
    out, _ = _run(pyr, xs, ys, valid, foot)
    assert np.isfinite(out).all()


def test_a_texel_of_inf_reaches_only_the_footprints_that_read_it():
    # a shared window's prefix sums would carry inf along its rows: such a run is read footprint by footprint,
    # so each pixel is what its own window gives (the reference reads each footprint through its own window)
    src = np.random.default_rng(7).uniform(0.0, 1.0, (64, 128, 3)).astype(np.float32)
    xs, ys, valid, foot = _lens_band("fisheye:fov=180")
    r = xs.shape[0] // 2
    p = xs.shape[1] // 2
    src[int(round(float(ys[r, p, 0]))), int(round(float(xs[r, p, 0])))] = np.inf
    pyr = pyramid(src, PANO)
    out, _ = _run(pyr, xs, ys, valid, foot)
    with np.errstate(invalid="ignore"):  # inf - inf in the reference's prefix sums: NaN, as in the kernel
        want, _ = fref.footprint(pyr, xs, ys, valid, foot, PANO.flags)
    out = out.reshape(-1, 3)
    finite = np.isfinite(want).all(axis=1)
    assert 0 < (~finite).sum() < 12  # the inf reaches the few footprints around it
    np.testing.assert_array_equal(np.isfinite(out).all(axis=1), finite)
    np.testing.assert_allclose(out[finite], want[finite], rtol=2 * EPS32, atol=2 * EPS32)


def test_antialias_gives_the_same_bits_on_one_two_and_three_threads():
    # bands are cut by the thread count; runs and shared sides stay within a row, so no pixel depends on the cut
    from lenslab.warp import warp
    from lenslab.warp.kernels.dispatch import set_threads

    img = np.random.default_rng(8).uniform(0.0, 4.0, (64, 128, 3)).astype(np.float32)
    src = Camera.from_spec("equirect", (128, 64))
    dst = Camera.from_spec("fisheye:fov=200", (60, 60), yaw=170.0)  # the seam and a pole in view
    outs = []
    try:
        for n in (1, 2, 3):
            set_threads(n)
            outs.append(warp(img, src, dst, antialias=True))  # bands of 60, 30 and 20 rows
    finally:
        set_threads(None)
    for out, alpha in outs[1:]:
        np.testing.assert_array_equal(out, outs[0][0])
        np.testing.assert_array_equal(alpha, outs[0][1])
