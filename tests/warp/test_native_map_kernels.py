"""The compiled map lattice (lenslab.warp.lattice) and separable samplers (lenslab.warp.filters) against their
NumPy references (lenslab.warp.kernels.lattice_reference, filter_reference), and against values from outside
the code: the Catmull-Rom spline and the Lanczos window transcribed here in float64, polynomials the ghost
nodes must continue exactly, and OpenCV's remap and copyMakeBorder.

Bounds: these kernels are built without fused multiply-adds and run the references' float64 steps in the
same order, so the references hold them bit for bit (``assert_array_equal``), Lanczos too: its sine and cosine
are the same Taylor polynomial in both, not the C library's and NumPy's. Against the transcribed formulas the order of operations differs: a few float64
ulp of the values (1e-12 relative).
"""

from __future__ import annotations

import cv2
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from lenslab.lenses import Camera
from lenslab.warp import lattice
from lenslab.warp.filters import sample
from lenslab.warp.kernels import filter_reference as fref
from lenslab.warp.kernels import lattice_reference as lref
from lenslab.warp.seam import Border, border_of, fold_piece, fold_taps, pad

EPS32 = float(np.finfo(np.float32).eps)


def catmull_rom(p0, p1, p2, p3, t):
    """The Catmull-Rom segment between p1 and p2 (Catmull and Rom 1974; tension 1/2), as usually written."""
    return 0.5 * (2.0 * p1 + (-p0 + p2) * t + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * t * t
                  + (-p0 + 3.0 * p1 - 3.0 * p2 + p3) * t ** 3)


def _band(shape, dirs=True):
    xs, ys = np.full(shape, np.nan, np.float32), np.full(shape, np.nan, np.float32)
    valid, need = np.zeros(shape, bool), np.full(shape, -9, np.int8)
    return xs, ys, valid, need, np.full(shape + (3,), np.nan) if dirs else np.full((1, 1, 1, 3), np.nan)


def _assert_band(got, want):
    xs, ys, valid, need, dirs = got
    wx, wy, wv, wn, wd = want
    np.testing.assert_array_equal(valid, wv)
    np.testing.assert_array_equal(need, wn)
    np.testing.assert_array_equal(xs, wx)
    np.testing.assert_array_equal(ys, wy)
    if dirs.shape == wd.shape:  # else the band has no room for directions, and no cell interpolates one
        np.testing.assert_array_equal(dirs[need == 2], wd[need == 2])
    else:
        assert not (need == 2).any()


# -- the lattice -------------------------------------------------------------------------------------------

@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), rows=st.integers(1, 14), cols=st.integers(1, 14),
       wrap=st.sampled_from([0.0, 40.0]), share=st.floats(0.0, 1.0))
def test_ghost_nodes_match_the_reference(seed, rows, cols, wrap, share):
    rng = np.random.default_rng(seed)
    nx, ny = rng.uniform(-60, 60, (2, rows, cols))
    valid = rng.uniform(size=(rows, cols)) < share
    got = lattice.ghost_nodes(nx, ny, valid, wrap)
    for a, b in zip(got, lref.ghost_nodes(nx, ny, valid, wrap)):
        np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize("wrap", [0.0, 100.0])
def test_ghost_nodes_continue_a_quadratic_exactly(wrap):
    """Three known nodes in a line determine a quadratic: the ghost one node beyond them is its value (up to
    float64 rounding of 3 x1 - 3 x2 + x3), and a node two beyond stays empty. A known node given on the other
    side of the seam (one period on) is the same point: x is continued unwrapped."""
    k = np.arange(10, dtype=np.float64)
    fx = 0.5 * k * k - 3.0 * k + 7.0  # f(k) = k^2 / 2 - 3 k + 7
    fy = -0.25 * k * k + 2.0 * k
    nx, ny = np.tile(fx, (6, 1)), np.tile(fy, (6, 1))
    valid = np.ones((6, 10), bool)
    valid[:, 7:] = False  # the right three nodes are missing
    given_x = nx.copy()
    given_x[:, 5] += wrap
    gx, gy, have = lattice.ghost_nodes(given_x, ny, valid, wrap)
    assert have[:, 7].all() and not have[:, 8:].any()
    np.testing.assert_allclose(gx[:, 7], nx[:, 7], rtol=0, atol=1e-12 * np.abs(fx).max())
    np.testing.assert_allclose(gy[:, 7], ny[:, 7], rtol=0, atol=1e-12 * np.abs(fy).max())


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), rows=st.integers(4, 12), cols=st.integers(4, 12),
       tx=st.floats(0.0, 1.0), ty=st.floats(0.0, 1.0), wrap=st.sampled_from([0.0, 50.0]))
def test_lattice_grid_matches_the_reference_and_the_catmull_rom_spline(seed, rows, cols, tx, ty, wrap):
    rng = np.random.default_rng(seed)
    nx, ny = rng.uniform(0, 20, (2, rows, cols))
    ox, oy = lattice.lattice_grid(nx, ny, tx, ty, wrap)
    rx, ry = lref.lattice_grid(nx, ny, tx, ty, wrap)
    np.testing.assert_array_equal(ox, rx)
    np.testing.assert_array_equal(oy, ry)
    # the spline, cell by cell: along x in each of the four rows, then along y (x values within 20 < wrap / 2
    # of each other: the unwrapping changes nothing)
    for cb in range(rows - 3):
        for ca in range(cols - 3):
            for got, nodes in ((ox, nx), (oy, ny)):
                p = nodes[cb:cb + 4, ca:ca + 4]
                along = [catmull_rom(*p[j], tx) for j in range(4)]
                want = catmull_rom(*along, ty)
                assert got[cb, ca] == pytest.approx(want, rel=1e-12, abs=1e-12)


def test_the_basis_is_the_catmull_rom_spline():
    t = np.linspace(0.0, 1.0, 11)
    powers = np.stack([t ** a for a in range(4)])
    for i in range(4):
        unit = np.eye(4)[i]
        np.testing.assert_allclose(lref.CR_BASIS[i] @ powers, catmull_rom(*unit, t), rtol=0, atol=1e-15)


def _random_lattice(rng, ncy, ncx, k=5):
    nodes = rng.uniform(0, 30, (k, ncy + 3, ncx + 3))
    choices = np.array([-1, 0, 1, 1, 1, 2] if k == 5 else [-1, 0, 1, 1], np.int8)
    return nodes, rng.choice(choices, size=(ncy, ncx))


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), ncy=st.integers(1, 8), ncx=st.integers(1, 8), k=st.sampled_from([2, 5]),
       wrap=st.sampled_from([0.0, 45.0]))
def test_cell_coefficients_match_the_reference_and_the_spline(seed, ncy, ncx, k, wrap):
    rng = np.random.default_rng(seed)
    nodes, state = _random_lattice(rng, ncy, ncx, k)
    cb0 = int(rng.integers(0, ncy))
    coef = np.zeros((ncy - cb0, ncx, k, 4, 4))
    lattice.cell_coefficients(nodes, state, cb0, ncy, wrap, coef)
    np.testing.assert_array_equal(coef, lref.cell_coefficients(nodes, state, cb0, ncy, wrap))
    # the polynomial of a state-1 cell is the spline through its stencil (values within 30 < wrap / 2)
    tx, ty = rng.uniform(0, 1, 2)
    for cb, ca in zip(*np.nonzero(state[cb0:] == 1)):
        p = nodes[1, cb0 + cb:cb0 + cb + 4, ca:ca + 4]
        want = catmull_rom(*[catmull_rom(*p[j], tx) for j in range(4)], ty)
        got = sum(coef[cb, ca, 1, b, a] * tx ** a * ty ** b for a in range(4) for b in range(4))
        assert got == pytest.approx(want, rel=1e-12, abs=1e-12)


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), step=st.sampled_from([1, 2, 3, 8]), width=st.integers(1, 40),
       height=st.integers(1, 12), samples=st.integers(1, 3), r0=st.integers(0, 5), per_pixel=st.booleans(),
       k=st.sampled_from([2, 5]))
def test_band_kernels_match_their_references(seed, step, width, height, samples, r0, per_pixel, k):
    rng = np.random.default_rng(seed)
    ncx, ncy = -(-width // step), -(-(height + r0) // step)
    nodes, state = _random_lattice(rng, ncy, ncx, k)
    coef = np.zeros((ncy, ncx, k, 4, 4))
    lattice.cell_coefficients(nodes, state, 0, ncy, 0.0, coef)
    shape = (height, width, samples)
    offs = rng.uniform(0, 1, (2, width, samples, 2) if per_pixel else (1, 1, samples, 2))
    offs[..., 0, :] = 0.5  # pixel centres: exactly on cell boundaries where step divides
    band = _band(shape, dirs=k == 5)
    if per_pixel:
        lattice.lattice_eval(coef, state, 0, float(step), r0, offs, *band)
        _assert_band(band, lref.lattice_eval(coef, state, 0, float(step), r0, offs, shape))
    else:
        lattice.lattice_rows(coef, state, 0, 1.0 / step, r0, offs, *band)
        _assert_band(band, lref.lattice_rows(coef, state, 0, 1.0 / step, r0, offs, shape))


def test_a_band_that_reads_beyond_its_coefficients_is_refused():
    rng = np.random.default_rng(0)
    nodes, state = _random_lattice(rng, 4, 4)
    coef = np.zeros((1, 4, 5, 4, 4))  # cell row 0 only
    offs = np.full((1, 1, 1, 2), 0.5)
    with pytest.raises(ValueError, match="beyond its coefficient rows"):
        lattice.lattice_rows(coef, state, 0, 1.0 / 8, 8, offs, *_band((4, 32, 1)))  # rows 8..11: cell row 1
    state[:] = 2
    with pytest.raises(ValueError, match="direction"):  # no room for the directions it would write
        lattice.lattice_rows(coef, state, 0, 1.0 / 8, 0, offs, *_band((4, 32, 1), dirs=False))


# -- the separable samplers and the folding ------------------------------------------------------------

CUBE = border_of(Camera.from_spec("cubemap", (48, 32)).lens)
PANO = Border(True, True, True)


@pytest.mark.parametrize("border", [Border(), PANO, CUBE], ids=["flat", "panorama", "cube"])
@pytest.mark.parametrize("name, kind", [("nearest", 0), ("bilinear", 1), ("bicubic", 2), ("lanczos", 3)])
@pytest.mark.parametrize("samples", [1, 3])
def test_separable_samplers_match_the_reference(border, name, kind, samples):
    rng = np.random.default_rng(kind + 7 * samples)
    src = rng.uniform(0.0, 4.0, (32, 48, 3)).astype(np.float32)
    shape = (20, 30, samples)
    xs = rng.uniform(-5, 52, shape).astype(np.float32)
    ys = rng.uniform(-5, 36, shape).astype(np.float32)
    xs.reshape(-1)[::5] = np.round(xs.reshape(-1)[::5])  # pixel centres: taps of weight 0
    valid = rng.uniform(size=shape) > 0.15
    out, alpha = np.zeros((20, 30, 3), np.float32), np.zeros((20, 30), np.float32)
    if kind == 1 and not border.has_pieces:  # bilinear without pieces is the float32 sampler: compare the tent
        from lenslab import cxx_kernels

        cxx_kernels.separable(src, xs, ys, valid, *border.flags, border.pieces, border.grid, *border.cell, 1, out,
                              alpha)
    else:
        sample(src, xs, ys, valid, border, name, out, alpha)
    want, want_alpha = fref.separable(src, xs, ys, valid, border, kind)
    np.testing.assert_array_equal(alpha.reshape(-1), want_alpha)
    np.testing.assert_array_equal(out.reshape(-1, 3), want)


@pytest.mark.parametrize("name", ["nearest", "bicubic", "lanczos"])
def test_positions_far_outside_or_not_numbers_read_an_edge_pixel(name):
    """A hostile map (a position of 1e30, or NaN marked valid) reads a pixel of the image, clamped at its edge
    (NaN: the left or top edge), never memory outside it."""
    src = np.arange(12, dtype=np.float32).reshape(3, 4, 1)
    xs = np.array([[[1e30], [-1e30], [np.nan], [1.0]]], np.float32)
    ys = np.array([[[1.0], [1.0], [1.0], [np.nan]]], np.float32)
    out, alpha = np.zeros((1, 4, 1), np.float32), np.zeros((1, 4), np.float32)
    sample(src, xs, ys, np.ones((1, 4, 1), bool), Border(), name, out, alpha)
    np.testing.assert_array_equal(out[0, :, 0], [7.0, 4.0, 4.0, 1.0])  # row 1's last and first pixels; row 0


def lanczos3(t):
    """sinc(t) sinc(t / 3) on |t| < 3 (the normalised sinc, sin(pi t) / (pi t))."""
    return np.where(np.abs(t) < 3.0, np.sinc(t) * np.sinc(t / 3.0), 0.0)


def keys(t, a=-0.5):
    """Keys' cubic convolution kernel (1981), a = -0.5: Catmull-Rom."""
    t = np.abs(t)
    return np.where(t <= 1, (a + 2) * t ** 3 - (a + 3) * t ** 2 + 1,
                    np.where(t < 2, a * t ** 3 - 5 * a * t ** 2 + 8 * a * t - 4 * a, 0.0))


@pytest.mark.parametrize("name, kern, rad", [("bicubic", keys, 2), ("lanczos", lanczos3, 3)])
def test_bicubic_and_lanczos_are_the_published_kernels(name, kern, rad):
    """Inside the image (no tap folded), the sample is the separable kernel's normalised weighted sum."""
    rng = np.random.default_rng(5)
    src = rng.uniform(0.0, 1.0, (24, 24, 1)).astype(np.float32)
    x = rng.uniform(4, 19, 200).astype(np.float32).astype(np.float64)  # a float32 map's positions
    y = rng.uniform(4, 19, 200).astype(np.float32).astype(np.float64)
    out, alpha = np.zeros((1, 200, 1), np.float32), np.zeros((1, 200), np.float32)
    sample(src, x[None, :, None], y[None, :, None], np.ones((1, 200, 1), bool), Border(), name, out, alpha)
    for q in range(200):
        i = np.arange(int(np.floor(x[q])) - rad + 1, int(np.floor(x[q])) + rad + 1)
        j = np.arange(int(np.floor(y[q])) - rad + 1, int(np.floor(y[q])) + rad + 1)
        wx, wy = kern(x[q] - i), kern(y[q] - j)
        want = (wy @ src[j][:, i, 0].astype(np.float64) @ wx) / (wx.sum() * wy.sum())
        # float64 sums in another order, then the float32 output's rounding (values below 1.5)
        assert out[0, q, 0] == pytest.approx(want, rel=0, abs=2 * EPS32)


def test_nearest_and_the_float64_tent_match_cv2_remap():
    """OpenCV's remap: nearest on positions away from ties, and bilinear on positions on its 1/32 px grid
    (where its fixed-point weights are exact); the tent through a cube map's pieces, inside one face."""
    rng = np.random.default_rng(2)
    src = rng.uniform(0.0, 1.0, (32, 48, 3)).astype(np.float32)
    # inside the front face (columns 16..31, rows 16..31 of a 3x2 layout of 16 px faces), one px in from its edges
    x = (np.round(rng.uniform(17, 30, 400) * 32) / 32).astype(np.float32)
    y = (np.round(rng.uniform(17, 30, 400) * 32) / 32).astype(np.float32)
    tie = (np.abs(x - np.floor(x) - 0.5) < 0.05) | (np.abs(y - np.floor(y) - 0.5) < 0.05)
    ones = np.ones((1, 400, 1), bool)
    for name, border, inter, keep in (("nearest", Border(), cv2.INTER_NEAREST, ~tie),
                                      ("bilinear", CUBE, cv2.INTER_LINEAR, np.ones(400, bool))):
        out, alpha = np.zeros((1, 400, 3), np.float32), np.zeros((1, 400), np.float32)
        sample(src, x[None, :, None], y[None, :, None], ones, border, name, out, alpha)
        theirs = cv2.remap(src, x[None, :], y[None, :], inter, borderMode=cv2.BORDER_REPLICATE)
        # bilinear: float64 weights here, float32 sums in OpenCV: a few float32 ulp of values below 1
        np.testing.assert_allclose(out[0][keep], theirs[0][keep], rtol=0, atol=4 * EPS32)


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_cube_folding_matches_the_reference(seed):
    rng = np.random.default_rng(seed)
    p = rng.integers(0, len(CUBE.pieces), 50)
    x0, y0 = CUBE.pieces[p, 0], CUBE.pieces[p, 1]
    i = x0 + rng.integers(-6, 22, 50)
    j = y0 + rng.integers(-6, 22, 50)
    want = fref.fold_piece(i, j, p, CUBE.pieces)
    for q in range(50):
        assert fold_piece(i[q], j[q], p[q], CUBE.pieces) == (want[0][q], want[1][q])


@pytest.mark.parametrize("wrap, mode", [(True, cv2.BORDER_WRAP), (False, cv2.BORDER_REPLICATE)])
def test_padding_matches_cv2_copy_make_border(wrap, mode):
    """Without poles, the border rules are OpenCV's: wrapped columns (rows replicated), or every edge replicated."""
    img = np.random.default_rng(1).uniform(0, 1, (9, 12, 3)).astype(np.float32)
    got = pad(img, Border(wrap, False, False), 3)
    rows = cv2.copyMakeBorder(img, 3, 3, 0, 0, cv2.BORDER_REPLICATE)
    want = cv2.copyMakeBorder(rows, 0, 0, 3, 3, mode)
    np.testing.assert_array_equal(got, want)


def test_a_tap_beyond_a_pole_reads_the_opposite_meridian():
    """Row -1 - j of column i is row j of column i + W/2 (and likewise below the bottom row)."""
    i, j = fold_taps([0, 5, 7, 3], [-1, -3, 10, 11], 12, 10, True, True, True)
    np.testing.assert_array_equal(i, [6, 11, 1, 9])
    np.testing.assert_array_equal(j, [0, 2, 9, 8])


@pytest.mark.parametrize("filter_name", ["nearest", "bicubic", "lanczos"])
@pytest.mark.parametrize("src_spec", ["equirect", "cubemap"])
def test_separable_warps_do_not_depend_on_the_thread_count(filter_name, src_spec):
    from lenslab.warp import warp
    from lenslab.warp.kernels.dispatch import set_threads

    src = Camera.from_spec(src_spec, (96, 64))
    img = np.random.default_rng(4).uniform(0, 1, (64, 96, 3)).astype(np.float32)
    dst = Camera.from_spec("fisheye:fov=200", (64, 64))
    try:
        set_threads(1)
        one = warp(img, src, dst, filter=filter_name, band_points=500)
        set_threads(3)
        many = warp(img, src, dst, filter=filter_name, band_points=500)
    finally:
        set_threads(None)
    for a, b in zip(one, many):
        np.testing.assert_array_equal(a, b)
