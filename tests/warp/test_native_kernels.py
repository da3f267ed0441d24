"""The compiled warp kernels (lenslab.cxx_kernels, C++) against their NumPy references
(lenslab.warp.kernels.reference) and against cv2.remap.

Bounds: the kernels run the references' float32 lerps and float64 weights in the same order, but the
compiler may fuse a multiply and an add into one rounding (-ffp-contract=fast, on CPUs with FMA). A fused
lerp ``a + t (b - a)`` differs from the two-rounding one by at most one rounding of each of its two
steps, so a bilinear value differs by at most 4 ulp of the largest tap (EPS32 * 4 * max|tap|). The
footprint filter's float64 weights differ by fusing (and the reference sums each texel's weights in
another order) by ~1e-15 relative: far below the float32 output's rounding, so 2 float32 ulp.
"""

from __future__ import annotations

import cv2
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from lenslab import cxx_kernels as K
from lenslab.warp.kernels import reference as ref
from lenslab.warp.pyramid import MAX_TAPS, pyramid
from lenslab.warp.seam import Border

EPS32 = float(np.finfo(np.float32).eps)
PANO = Border(True, True, True)  # a full-turn panorama: wraps, both edges poles
FLAT = Border()  # a flat image: clamps


def _src(h, w, nc, seed=0):
    return np.random.default_rng(seed).uniform(0.0, 1.0, (h, w, nc)).astype(np.float32)


def _positions(n, w, h, seed=1, margin=2.0):
    """Index coordinates inside and up to ``margin`` px beyond every edge, plus exact pixel centres."""
    rng = np.random.default_rng(seed)
    x = rng.uniform(-margin, w - 1 + margin, n).astype(np.float32)
    y = rng.uniform(-margin, h - 1 + margin, n).astype(np.float32)
    x[: n // 8] = np.round(x[: n // 8])
    valid = rng.uniform(size=n) > 0.1
    return x, y, valid


@pytest.mark.parametrize("nc", [1, 3, 4, 5])
@pytest.mark.parametrize("border", [PANO, FLAT], ids=["panorama", "flat"])
def test_single_tap_bilinear_matches_the_numpy_reference(nc, border):
    src = _src(17, 32, nc)
    x, y, v = _positions(5000, 32, 17)
    out = np.full((5000, nc), np.nan, np.float32)
    alpha = np.full(5000, np.nan, np.float32)
    K.bilinear1(src.reshape(-1), 32, 17, nc, x, y, v, *border.flags, out, alpha)
    want, want_alpha = ref.bilinear1(src, x, y, v, border.flags)
    np.testing.assert_array_equal(alpha, want_alpha)
    np.testing.assert_allclose(out, want, rtol=0, atol=4 * EPS32 * src.max())
    assert np.all(out[~v] == 0.0)


@pytest.mark.parametrize("nc", [1, 3, 4])
def test_bilinear_on_a_1_32_pixel_grid_matches_cv2_remap(nc):
    """On positions that are multiples of 1/32 px, cv2.remap's fixed-point weights are exact: both
    compute the same bilinear value, up to the rounding of their different sums (4 ulp)."""
    src = _src(40, 64, nc, seed=3)
    rng = np.random.default_rng(4)
    x = (rng.integers(0, 63 * 32, (50, 70)) / 32).astype(np.float32)
    y = (rng.integers(0, 39 * 32, (50, 70)) / 32).astype(np.float32)
    theirs = cv2.remap(src, x, y, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE).reshape(50, 70, nc)
    out = np.empty((50, 70, nc), np.float32)
    alpha = np.empty((50, 70), np.float32)
    K.bilinear1(src.reshape(-1), 64, 40, nc, x, y, np.ones((50, 70), bool), False, False, False, out, alpha)
    np.testing.assert_allclose(out, theirs, rtol=0, atol=4 * EPS32 * src.max())
    assert np.all(alpha == 1.0)


@pytest.mark.parametrize("ns", [2, 4, 16])
def test_supersampled_bilinear_matches_the_numpy_reference(ns):
    src = _src(16, 32, 3, seed=5)
    x, y, v = _positions(300 * ns, 32, 16, seed=ns)
    x, y, v = x.reshape(300, ns), y.reshape(300, ns), v.reshape(300, ns)
    out = np.empty((300, 3), np.float32)
    alpha = np.empty(300, np.float32)
    K.bilinear_n(src.reshape(-1), 32, 16, 3, x, y, v, *PANO.flags, out, alpha)
    want, want_alpha = ref.bilinear_n(src, x, y, v, PANO.flags)
    np.testing.assert_array_equal(alpha, want_alpha)
    # each sample within 4 ulp; the mean of n of them within 4 ulp of the largest too (weights sum to 1)
    np.testing.assert_allclose(out, want, rtol=0, atol=(4 + ns) * EPS32 * src.max())


@pytest.mark.parametrize("nc", [1, 3, 4])
def test_taps_are_the_references_and_read_as_the_single_tap_sampler(nc):
    src = _src(20, 30, nc, seed=6)
    x, y, v = _positions(4000, 30, 20, seed=7)
    off = np.empty(4000, np.uint32)
    tx = np.empty(4000, np.float32)
    ty = np.empty(4000, np.float32)
    K.taps_of(30, 20, x, y, v, off, tx, ty)
    want_off, want_tx, want_ty = ref.taps(src, x, y, v)
    np.testing.assert_array_equal(off, want_off)
    np.testing.assert_array_equal(tx, want_tx)  # float32 differences of float32 values: exact
    np.testing.assert_array_equal(ty, want_ty)
    out = np.full((4000, nc), np.nan, np.float32)
    alpha = np.full(4000, np.nan, np.float32)
    K.from_taps(src.reshape(-1), 30, nc, off, tx, ty, out, alpha)
    fold = np.flatnonzero(off == ref.FOLDED)
    assert len(fold) > 100  # the positions reach beyond every edge
    K.folded(src.reshape(-1), 30, 20, nc, fold, x[fold], y[fold], *PANO.flags, out, alpha)
    one = np.empty_like(out)
    one_alpha = np.empty_like(alpha)
    K.bilinear1(src.reshape(-1), 30, 20, nc, x, y, v, *PANO.flags, one, one_alpha)
    np.testing.assert_array_equal(out, one)  # the same lerps from the same fractions: the same bits
    np.testing.assert_array_equal(alpha, one_alpha)
    want, _ = ref.bilinear1(src, x, y, v, PANO.flags)
    np.testing.assert_allclose(out, want, rtol=0, atol=4 * EPS32)


def _footprints(n, rng, longest):
    """Footprint sides: isotropic boxes, axis-aligned and rotated anisotropic ones, up to ``longest`` px."""
    size = np.exp(rng.uniform(np.log(0.05), np.log(longest), n))
    aspect = np.exp(rng.uniform(0.0, np.log(12.0), n))
    theta = rng.uniform(0.0, np.pi, n)
    theta[: n // 4] = 0.0  # axis-aligned: the one-box path
    aspect[: n // 8] = 1.0
    c, s = np.cos(theta), np.sin(theta)
    a = np.stack([c * size, s * size], axis=-1)
    b = np.stack([-s * size / aspect, c * size / aspect], axis=-1)
    return np.concatenate([a, b], axis=-1).astype(np.float32)


@pytest.mark.parametrize("nc", [1, 3, 4])
@pytest.mark.parametrize("ns", [1, 4])
def test_footprint_filter_matches_the_numpy_reference(nc, ns):
    rng = np.random.default_rng(10 * nc + ns)
    src = _src(32, 64, nc, seed=nc)
    pyr = pyramid(src, PANO)
    n = 600
    x = rng.uniform(-0.5, 63.5, (n, ns)).astype(np.float32)
    y = rng.uniform(-0.5, 31.5, (n, ns)).astype(np.float32)
    y[:40] = rng.uniform(-0.5, 1.0, (40, ns))  # beside the pole
    valid = rng.uniform(size=(n, ns)) > 0.1
    foot = _footprints(n * ns, rng, 40.0).reshape(n, ns, 4)
    out = np.empty((n, nc), np.float32)
    alpha = np.empty(n, np.float32)
    K.footprint(pyr.level0, pyr.rest, pyr.shapes, pyr.offsets, x, y, valid, foot, *PANO.flags, MAX_TAPS,
                out, alpha)
    want, want_alpha = ref.footprint(pyr, x, y, valid, foot, PANO.flags)
    np.testing.assert_array_equal(alpha, want_alpha)
    np.testing.assert_allclose(out, want, rtol=2 * EPS32, atol=2 * EPS32 * src.max())


def test_footprint_of_a_constant_image_is_that_constant():
    """Every weight set is normalised: a constant source gives the constant whatever the footprint."""
    src = np.full((32, 64, 3), 0.375, np.float32)
    pyr = pyramid(src, PANO)
    rng = np.random.default_rng(2)
    foot = _footprints(2000, rng, 60.0).reshape(2000, 1, 4)
    x = rng.uniform(-0.5, 63.5, (2000, 1)).astype(np.float32)
    y = rng.uniform(-0.5, 31.5, (2000, 1)).astype(np.float32)
    out = np.empty((2000, 3), np.float32)
    alpha = np.empty(2000, np.float32)
    K.footprint(pyr.level0, pyr.rest, pyr.shapes, pyr.offsets, x, y, np.ones((2000, 1), bool), foot,
                *PANO.flags, MAX_TAPS, out, alpha)
    np.testing.assert_allclose(out, 0.375, rtol=1e-6)


def test_kernels_refuse_mismatched_arrays():
    src = _src(4, 4, 3)
    with pytest.raises(ValueError, match="shapes differ"):
        K.bilinear1(src.reshape(-1), 4, 4, 3, np.zeros(5, np.float32), np.zeros(4, np.float32), np.ones(5, bool),
                    False, False, False, np.empty((5, 3), np.float32), np.empty(5, np.float32))
    with pytest.raises(TypeError):  # a strided output is refused, never written through a copy
        K.bilinear1(src.reshape(-1), 4, 4, 3, np.zeros(2, np.float32), np.zeros(2, np.float32), np.ones(2, bool),
                    False, False, False, np.empty((2, 6), np.float32)[:, ::2], np.empty(2, np.float32))


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf, None])
def test_all_finite_agrees_with_numpy(bad):
    rng = np.random.default_rng(8)
    a = rng.normal(0, 1e30, 100_003).astype(np.float32)
    a[:5] = (-0.0, 1e-45, 3.4e38, -3.4e38, 0.0)  # signed zero, the smallest subnormal, the largest finite
    for pos in (0, 50_000, 100_002):
        b = a.copy()
        if bad is not None:
            b[pos] = bad
        assert K.all_finite(b) == bool(np.isfinite(b).all())


@pytest.mark.parametrize("pieces", [None, "grid", "uneven"])
@pytest.mark.parametrize("wrap", [0.0, 64.0])
def test_neighbour_secants_match_the_numpy_reference(pieces, wrap):
    rng = np.random.default_rng(int(wrap) + len(pieces or ""))
    nrows, w, top, h = 14, 24, 1, 12
    rows, cols = np.mgrid[5:5 + nrows, 0:w]
    piece = {None: None, "grid": (cols // 8) * 10 + rows // 6,  # a grid of 8 x 6 pieces; pieces of two
             "uneven": np.where(cols < 16, rows // 8, 2 + rows // 4)}[pieces]  # sizes, as a split barrel's
    piece = None if piece is None else piece.astype(np.int32)
    xs = rng.uniform(-2, 66, (nrows, w)).astype(np.float32)
    ys = rng.uniform(-2, 34, (nrows, w)).astype(np.float32)
    vs = rng.uniform(size=(nrows, w)) > 0.25
    foot = np.full((h, w, 1, 4), np.nan, np.float32)
    edge = np.zeros((h, w, 1), bool)
    K.neighbour_secants(xs, ys, vs, top, wrap, np.zeros((0, 0), np.int32) if piece is None else piece, foot,
                        edge)
    want, want_edge = ref.neighbour_secants(xs, ys, vs, top, h, wrap, piece)
    np.testing.assert_array_equal(edge[..., 0], want_edge)
    # float64 steps rounded once to float32; a fused multiply-add in the unwrapping may move that by 1 ulp
    np.testing.assert_allclose(foot[:, :, 0], want, rtol=EPS32, atol=EPS32 * 70)
