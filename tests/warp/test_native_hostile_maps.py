"""Hostile map positions and footprints through the compiled samplers (lenslab.cxx_kernels).

A map handed to the warp (``lenslab.warp.given``, a lens that returns 1e30 or NaN near a fold-over) may hold
positions far outside the source, infinite or NaN and still be marked valid. Every sampler then reads a
pixel of the source clamped at its edge (NaN: the left or top edge), the same one the separable samplers read
(tests/warp/test_native_map_kernels.py), in bounded time, never memory outside the source and never a value
the source does not hold. The expected values are the source array's own pixels, indexed in the test.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from lenslab import cxx_kernels as K
from lenslab.warp.filters import sample
from lenslab.warp.kernels import reference as ref
from lenslab.warp.pyramid import MAX_TAPS, pyramid
from lenslab.warp.seam import Border
from lenslab.warp.taps import INVALID, FOLDED

FAR = [1e30, -1e30, np.inf, -np.inf, np.nan, 3e9, -3e9, 1e17]
SRC = np.arange(3 * 4, dtype=np.float32).reshape(3, 4, 1)  # pixel (row j, column i) holds 4 j + i


def _edge_pixel(x, y):
    """The pixel a position reads when it lies beyond the image: clamped into it, NaN at the left/top edge."""
    def clamp(v, n):
        return 0 if np.isnan(v) else int(min(max(np.floor(v), 0), n - 1))
    return float(SRC[clamp(y, 3), clamp(x, 4), 0])


CASES = [(x, 1.0) for x in FAR] + [(2.0, y) for y in FAR]


@pytest.mark.parametrize("samples", [1, 2])
@pytest.mark.parametrize("name", ["bilinear", "nearest", "bicubic", "lanczos"])
def test_every_filter_reads_the_edge_pixel_for_a_position_far_outside(name, samples):
    n = len(CASES)
    xs = np.array([[[x] * samples for x, _ in CASES]], np.float32)
    ys = np.array([[[y] * samples for _, y in CASES]], np.float32)
    out, alpha = np.zeros((1, n, 1), np.float32), np.zeros((1, n), np.float32)
    sample(SRC, xs, ys, np.ones((1, n, samples), bool), Border(), name, out, alpha)
    np.testing.assert_array_equal(out[0, :, 0], [_edge_pixel(x, y) for x, y in CASES])
    np.testing.assert_array_equal(alpha, 1.0)


def test_cached_taps_fold_a_position_far_outside_onto_the_edge_pixel():
    x = np.array([x for x, _ in CASES], np.float32)
    y = np.array([y for _, y in CASES], np.float32)
    v = np.ones(len(CASES), bool)
    off, tx, ty = np.empty(len(x), np.uint32), np.empty(len(x), np.float32), np.empty(len(x), np.float32)
    K.taps_of(4, 3, x, y, v, off, tx, ty)
    assert np.all(off == FOLDED)  # every one crosses an edge: the folding sampler reads it
    out, alpha = np.zeros((len(x), 1), np.float32), np.zeros(len(x), np.float32)
    K.folded(SRC.reshape(-1), 4, 3, 1, np.arange(len(x), dtype=np.int64), x, y, False, False, False, out, alpha)
    np.testing.assert_array_equal(out[:, 0], [_edge_pixel(a, b) for a, b in CASES])


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(st.floats(width=32), st.floats(width=32)), min_size=1, max_size=20),
       st.sampled_from([(True, True, True), (False, False, False), (True, False, False)]))
def test_bilinear_of_any_float32_position_is_a_weighted_mean_of_source_pixels(pts, flags):
    """Any float32 position (NaN and inf included) gives a value between the source's least and largest
    pixel, and the kernels agree with their NumPy reference."""
    x = np.array([p[0] for p in pts], np.float32)
    y = np.array([p[1] for p in pts], np.float32)
    v = np.ones(len(pts), bool)
    out, alpha = np.zeros((len(pts), 1), np.float32), np.zeros(len(pts), np.float32)
    K.bilinear1(SRC.reshape(-1), 4, 3, 1, x, y, v, *flags, out, alpha)
    assert np.all((out >= 0.0) & (out <= 11.0))
    want, _ = ref.bilinear1(SRC, x, y, v, flags)
    np.testing.assert_allclose(out, want, rtol=0, atol=4 * 11.0 * np.finfo(np.float32).eps)
    off, tx, ty = np.empty(len(x), np.uint32), np.empty(len(x), np.float32), np.empty(len(x), np.float32)
    K.taps_of(4, 3, x, y, v, off, tx, ty)
    woff, wtx, wty = ref.taps(SRC, x, y, v)
    np.testing.assert_array_equal(off, woff)
    np.testing.assert_array_equal(tx, wtx)
    np.testing.assert_array_equal(ty, wty)


# a constant panorama: whatever a footprint covers, its mean is the constant
CONST = np.full((8, 16, 1), 0.25, np.float32)


@pytest.mark.timeout(120)  # a guard against the hang this test pins, far above its milliseconds
@pytest.mark.parametrize("pos", [1e30, -1e30, np.inf, np.nan, 1e17, 3.0])
@pytest.mark.parametrize("side", [1.0, 1e30, np.inf, np.nan, 1e12])
def test_footprint_filter_of_hostile_positions_and_sides_reads_the_source(pos, side):
    """A footprint at 1e30 or NaN, or with sides of 1e30, inf or NaN (a map's neighbours a fold-over apart)
    gives the constant of a constant source, and returns (it looped over 1e30 texel rows)."""
    pyr = pyramid(CONST, Border())
    x = np.array([[pos], [3.0]], np.float32)
    y = np.array([[2.0], [pos]], np.float32)
    foot = np.array([[[side, 0.0, 0.0, side]]] * 2, np.float32)
    out, alpha = np.zeros((2, 1), np.float32), np.zeros(2, np.float32)
    K.footprint(pyr.level0, pyr.rest, pyr.shapes, pyr.offsets, x, y, np.ones((2, 1), bool), foot, False, False,
                False, MAX_TAPS, out, alpha)
    np.testing.assert_allclose(out[:, 0], 0.25, rtol=1e-6)  # float64 weights normalised, then rounded to float32
    np.testing.assert_array_equal(alpha, 1.0)


def test_footprint_reference_reads_hostile_footprints_as_the_kernel_does():
    """The NumPy reference clamps positions and sides as the kernel does (same window, same weights)."""
    pyr = pyramid(np.random.default_rng(3).uniform(0, 1, (8, 16, 2)).astype(np.float32), Border(True, True, True))
    vals = [1e30, -1e30, np.inf, np.nan, 2.5]
    x = np.array([[a] for a in vals for _ in vals], np.float32)
    y = np.full_like(x, 3.0)
    foot = np.array([[[b, 0.3, -0.2, b]] for _ in vals for b in vals], np.float32)
    out, alpha = np.zeros((len(x), 2), np.float32), np.zeros(len(x), np.float32)
    K.footprint(pyr.level0, pyr.rest, pyr.shapes, pyr.offsets, x, y, np.ones(x.shape, bool), foot, True, True, True,
                MAX_TAPS, out, alpha)
    want, want_alpha = ref.footprint(pyr, x, y, np.ones(x.shape, bool), foot, (True, True, True))
    np.testing.assert_array_equal(alpha, want_alpha)
    np.testing.assert_allclose(out, want, rtol=0, atol=2 * np.finfo(np.float32).eps)  # fused float64 weights


def _image(h=3, w=4, nc=1):
    return np.zeros(h * w * nc, np.float32)


@pytest.mark.parametrize("call", [
    # a source smaller than the sizes passed with it: the kernel would read past its end
    lambda: K.folded(_image(), 100, 100, 1, np.zeros(1, np.int64), np.full(1, 50, np.float32),
                     np.full(1, 50, np.float32), False, False, False, np.zeros((1, 1), np.float32), np.zeros(1, np.float32)),
    lambda: K.bilinear1(_image(), -1, -12, 1, np.zeros(1, np.float32), np.zeros(1, np.float32), np.ones(1, bool),
                        False, False, False, np.zeros((1, 1), np.float32), np.zeros(1, np.float32)),
    lambda: K.bilinear1(_image(), 2 ** 32, 2 ** 32, 1, np.zeros(1, np.float32), np.zeros(1, np.float32),
                        np.ones(1, bool), False, False, False, np.zeros((1, 1), np.float32), np.zeros(1, np.float32)),
    # a cached tap beyond the source
    lambda: K.from_taps(_image(), 4, 1, np.array([11], np.uint32), np.zeros(1, np.float32), np.zeros(1, np.float32),
                        np.zeros((1, 1), np.float32), np.zeros(1, np.float32)),
    # a folded pixel's output row beyond out
    lambda: K.folded(_image(), 4, 3, 1, np.zeros(1, np.int64), np.zeros(1, np.float32), np.zeros(1, np.float32),
                     False, False, False, np.zeros((1, 0), np.float32), np.zeros(1, np.float32)),
    # a source too large for 32-bit taps
    lambda: K.taps_of(2 ** 16, 2 ** 16, np.zeros(1, np.float32), np.zeros(1, np.float32), np.ones(1, bool),
                      np.zeros(1, np.uint32), np.zeros(1, np.float32), np.zeros(1, np.float32)),
    # pyramid levels larger than their buffers
    lambda: K.footprint(_image(), np.zeros(1, np.float32), np.array([[30, 40]], np.int64), np.zeros(1, np.int64),
                        np.zeros((1, 1), np.float32), np.zeros((1, 1), np.float32), np.ones((1, 1), bool),
                        np.ones((1, 1, 4), np.float32), False, False, False, MAX_TAPS, np.zeros((1, 1), np.float32),
                        np.zeros(1, np.float32)),
    lambda: K.footprint(_image(8, 8), np.zeros(4, np.float32), np.array([[8, 8], [4, 4]], np.int64),
                        np.array([0, 0], np.int64), np.zeros((1, 1), np.float32), np.zeros((1, 1), np.float32),
                        np.ones((1, 1), bool), np.full((1, 1, 4), 50.0, np.float32), False, False, False, MAX_TAPS,
                        np.zeros((1, 1), np.float32), np.zeros(1, np.float32)),
], ids=["folded-source", "negative-size", "size-overflow", "tap-beyond", "folded-out", "taps-32bit",
        "level0-small", "rest-small"])
def test_sizes_that_disagree_with_the_arrays_are_refused_before_any_read(call):
    with pytest.raises(ValueError):
        call()


def test_cached_taps_of_a_one_row_source_all_fold():
    """A source one pixel tall has no 2x2 inside it: every tap goes through the folding sampler, and the
    bounds check of the cached taps lets that band through."""
    src = np.array([1.0, 2.0, 3.0], np.float32)
    off = np.array([FOLDED, INVALID], np.uint32)
    out, alpha = np.full((2, 1), 7.0, np.float32), np.full(2, 7.0, np.float32)
    K.from_taps(src, 3, 1, off, np.zeros(2, np.float32), np.zeros(2, np.float32), out, alpha)
    np.testing.assert_array_equal(out[:, 0], [7.0, 0.0])  # folded: left for the folding sampler; invalid: 0
    np.testing.assert_array_equal(alpha, [7.0, 0.0])


@pytest.mark.parametrize("offset,inv", [(1e300, 1.0 / 8), (-1e300, 1.0 / 8), (0.5, 1e-300), (0.5, 1e300)],
                         ids=["offset-far-right", "offset-far-left", "step-1e300", "step-1e-300"])
def test_lattice_offsets_and_steps_beyond_any_image_are_refused(offset, inv):
    """The row walk converts ceil(edge / inv - offset) to an integer: an offset of 1e300 or a step of 1e300
    pixels per cell would convert a value beyond int64 (undefined), so the binding refuses them."""
    shape = (4, 32, 1)
    state = np.ones((4, 4), np.int8)
    coef = np.zeros((4, 4, 2, 4, 4))
    offs = np.full((1, 1, 1, 2), offset)
    band = (np.zeros(shape, np.float32), np.zeros(shape, np.float32), np.zeros(shape, bool), np.zeros(shape, np.int8),
            np.zeros((1, 1, 1, 3)))
    with pytest.raises(ValueError, match="beyond"):
        K.lattice_rows(coef, state, 0, inv, 0, offs, *band)
    with pytest.raises(ValueError, match="beyond"):
        K.lattice_eval(coef, state, 0, 1.0 / inv, 0, offs, *band)
    K.lattice_rows(coef, state, 0, 1.0 / 8, 0, np.full((1, 1, 1, 2), 0.5), *band)  # in range: evaluated
    assert band[2].all()


def test_a_cell_state_beyond_2_is_refused_not_read_as_a_direction():
    """States are -1 (no source), 0 (exact), 1 (position) and 2 (direction); a 3 would make the kernels read and
    write a direction's three coefficient sets in a lattice that holds two."""
    state = np.ones((4, 4), np.int8)
    state[2, 1] = 3
    nodes = np.zeros((2, 7, 7))
    with pytest.raises(ValueError, match="cell states"):
        K.cell_coefficients(nodes, state, 0, 4, 0.0, np.zeros((4, 4, 2, 4, 4)))
    shape = (32, 32, 1)
    band = (np.zeros(shape, np.float32), np.zeros(shape, np.float32), np.zeros(shape, bool), np.zeros(shape, np.int8),
            np.zeros(shape + (3,)))
    with pytest.raises(ValueError, match="cell states"):
        K.lattice_rows(np.zeros((4, 4, 2, 4, 4)), state, 0, 1.0 / 8, 0, np.full((1, 1, 1, 2), 0.5), *band)
    state[2, 1] = -1  # no source: allowed
    K.cell_coefficients(nodes, state, 0, 4, 0.0, np.zeros((4, 4, 2, 4, 4)))


@pytest.mark.parametrize("out,alpha", [
    (np.zeros((1, 2, 1)), np.zeros((1, 2), np.float32)),  # float64
    (np.zeros((1, 4, 1), np.float32)[:, ::2], np.zeros((1, 2), np.float32)),  # strided
    (np.zeros((1, 2, 1), np.float32), np.zeros((1, 2), np.int32)),
], ids=["float64-out", "strided-out", "int-alpha"])
def test_sample_refuses_outputs_it_cannot_write_in_one_line(out, alpha):
    """filters.sample writes its outputs in place: another dtype or a strided view is a one-line WarpError
    naming the array, not the extension's page of signatures."""
    from lenslab.errors import WarpError

    xs = np.zeros((1, 2, 1), np.float32)
    with pytest.raises(WarpError) as caught:
        sample(SRC, xs, xs, np.ones((1, 2, 1), bool), Border(), "bilinear", out, alpha)
    assert "\n" not in str(caught.value) and ("out" in str(caught.value) or "alpha" in str(caught.value))


# -- footprints beyond the coarsest pyramid level ---------------------------------------------------------


def _rotated(n, rng, lo, hi):
    """Parallelograms of sides lo..hi texels at any angle (the window of 24 texels clips them)."""
    size, theta = rng.uniform(lo, hi, n), rng.uniform(0.0, np.pi, n)
    aspect = rng.uniform(1.0, 8.0, n)
    c, s = np.cos(theta), np.sin(theta)
    return np.stack([c * size, s * size, -s * size / aspect, c * size / aspect], axis=-1).astype(np.float32)


def test_a_footprint_larger_than_the_window_reads_its_centre_never_nan():
    """A 625-row source has no coarser level (625 is odd): a rotated footprint of 100 to 400 texels is clipped to
    a window of 24 texels. That window lies on the footprint's centre, so a constant source gives the constant
    (the window at the footprint's top-left corner could miss a rotated footprint altogether: 0 / 0 = NaN)."""
    rng = np.random.default_rng(5)
    pyr = pyramid(np.full((25, 1250, 1), 0.5, np.float32), Border(True, False, False))
    n = 2000
    x = rng.uniform(0.0, 1249.0, (n, 1)).astype(np.float32)
    y = rng.uniform(0.0, 24.0, (n, 1)).astype(np.float32)
    foot = _rotated(n, rng, 100.0, 400.0).reshape(n, 1, 4)
    out, alpha = np.empty((n, 1), np.float32), np.empty(n, np.float32)
    K.footprint(pyr.level0, pyr.rest, pyr.shapes, pyr.offsets, x, y, np.ones((n, 1), bool), foot, True, False, False,
                MAX_TAPS, out, alpha)
    np.testing.assert_allclose(out[:, 0], 0.5, rtol=1e-6)


def test_a_clipped_footprint_averages_the_texels_around_its_centre():
    """A box of 1000 texels centred between columns 30 and 31 of a source that is 0 up to column 30 and 1 from
    31: the centred window holds 12 texels of each, every one wholly inside the box, so the mean is 1/2 (the
    window at the box's top-left corner read only zeros)."""
    src = np.zeros((25, 62, 1), np.float32)
    src[:, 31:] = 1.0
    pyr = pyramid(src, Border())
    out, alpha = np.empty((1, 1), np.float32), np.empty(1, np.float32)
    K.footprint(pyr.level0, pyr.rest, pyr.shapes, pyr.offsets, np.array([[30.5]], np.float32),
                np.array([[12.0]], np.float32), np.ones((1, 1), bool),
                np.array([[[1000.0, 0.0, 0.0, 1000.0]]], np.float32), False, False, False, MAX_TAPS, out, alpha)
    np.testing.assert_allclose(out[0, 0], 0.5, rtol=1e-6)


def test_a_thumbnail_of_a_panorama_without_coarser_levels_has_no_nan():
    """lenslab.warp with --antialias: a 1250 x 625 constant panorama into a 16 x 16 fisheye of 360 degrees gives
    the constant wherever a sample lands (the engine's promise: no NaN)."""
    from lenslab.lenses import Camera
    from lenslab.warp import warp

    img = np.full((625, 1250, 3), 0.5, np.float32)
    out, alpha = warp(img, Camera.from_spec("equirect", (1250, 625)), Camera.from_spec("fisheye:fov=360", (16, 16)),
                      antialias=True)
    assert not np.isnan(out).any()
    inside = alpha > 0
    np.testing.assert_allclose(out[inside] / alpha[inside][:, None], 0.5, rtol=1e-5)


@pytest.mark.parametrize("filter_name,antialias", [("bilinear", False), ("nearest", False), ("bicubic", False),
                                                   ("bilinear", True)])
def test_an_inverse_map_far_outside_reads_the_edge_pixel(filter_name, antialias):
    """warp_with_map: a map position of +-1e30 is "outside the source: its edge", as its docstring says, never
    NaN or a value the source does not hold (+1e30 read the left edge before, through an out-of-range float to
    integer conversion)."""
    from lenslab.warp.given import warp_with_map

    src = np.arange(12, dtype=np.float32).reshape(3, 4)
    xy = np.array([[[1e30, 1.5], [-1e30, 1.5], [2.5, 1e30], [2.5, -1e30]]])
    out, alpha = warp_with_map(src, xy, filter=filter_name, antialias=antialias)
    assert np.all(np.isfinite(out)) and np.all(alpha == 1.0)
    if not antialias:  # one tap: exactly the pixel at the edge (row 1 right, row 1 left, row 2 col 2, row 0 col 2)
        np.testing.assert_array_equal(out[0], [7.0, 4.0, 10.0, 2.0])
    else:  # footprints of neighbours 1e30 apart: means of source pixels
        assert np.all((out >= 0.0) & (out <= 11.0))
