"""The pyramid's levels (``halve``, vectorised four doubles at a time where the CPU has AVX2) against 2x2 box
means computed by NumPy in float64, for every channel count the vector paths treat apart (1, 2, 3, 4 and the
groups of four of wider pixels), odd widths and values from 1e-30 to 3e38."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.warp.kernels import native
from lenslab.warp.kernels.dispatch import set_threads
from lenslab.warp.kernels.pyramid_reference import halve as halve_reference
from lenslab.warp.pyramid import pyramid
from lenslab.warp.seam import Border


def _hostile(rng, shape):
    """Signed values over 60 decades, the largest near float32's limit, and exact zeros."""
    mag = np.exp(rng.uniform(np.log(1e-30), np.log(3e38), shape))
    v = (mag * rng.choice([-1.0, 1.0], shape)).astype(np.float32)
    v[rng.uniform(size=shape) < 0.05] = 0.0
    return v


@pytest.mark.parametrize("nc", [1, 2, 3, 4, 5, 6, 7, 9])
@pytest.mark.parametrize("size", [(2, 2), (6, 10), (4, 18), (8, 34), (6, 35)])  # a last column left out: 35
def test_halve_is_the_2x2_box_mean(nc, size):
    rng = np.random.default_rng(nc * 100 + size[1])
    src = _hostile(rng, size + (nc,))
    out = np.full((size[0] // 2, size[1] // 2, nc), np.nan, np.float32)
    native.kernels().halve(np.ascontiguousarray(src[:, :size[1] // 2 * 2]), out)
    # the reference's steps: the horizontal pairs summed in float64, then the two rows, times 1/4, rounded once
    np.testing.assert_array_equal(out, halve_reference(src))
    # an outside value: the exact mean of each block. The float64 sum of four float32 values errs by at most three
    # roundings of 2^-53 of the largest magnitude (none while they lie within 2^29 of each other), and the result is
    # rounded once to float32: within half a float32 ulp of the exact mean, plus 2^-51 of the block's largest value
    d = src[:size[0] // 2 * 2, :size[1] // 2 * 2].astype(np.float64).reshape(size[0] // 2, 2, size[1] // 2, 2, nc)
    mean, largest = d.mean(axis=(1, 3)), np.abs(d).max(axis=(1, 3))
    assert np.isfinite(out).all()
    half_ulp = np.spacing(np.abs(mean).astype(np.float32)).astype(np.float64) / 2
    assert (np.abs(out - mean) <= half_ulp + largest * 2.0**-51).all()


def test_halve_of_small_integers_is_exact():
    # means of whole numbers are multiples of 1/4: exact in float32, so the box mean itself is the value
    rng = np.random.default_rng(3)
    for nc in (1, 2, 3, 4, 6):
        src = rng.integers(-1000, 1000, (8, 22, nc)).astype(np.float32)
        out = np.empty((4, 11, nc), np.float32)
        native.kernels().halve(src, out)
        want = src.reshape(4, 2, 11, 2, nc).astype(np.float64).sum(axis=(1, 3)) / 4.0
        np.testing.assert_array_equal(out, want.astype(np.float32))


def test_the_whole_pyramid_is_the_same_on_any_thread_count():
    """Each level is the 2x2 means of the one before, whatever the threads its rows are split over."""
    src = _hostile(np.random.default_rng(4), (96, 192, 3))
    levels = []
    try:
        for n in (1, 2, 3):
            set_threads(n)
            pyr = pyramid(src, Border(True, True, True))
            levels.append(pyr.rest.copy())
    finally:
        set_threads(None)
    np.testing.assert_array_equal(levels[1], levels[0])
    np.testing.assert_array_equal(levels[2], levels[0])
    cur = src
    for lev in range(1, len(pyr.shapes)):
        nxt = halve_reference(cur)
        np.testing.assert_array_equal(pyr.level(lev), nxt)
        cur = nxt
