"""The row-wise lattice kernel (offsets shared by every pixel, walked cell by cell) against the general
one that finds each sample's cell on its own (:func:`lenslab.warp.lattice.lattice_eval`), on random
lattices: the same cell for every sample (a wrong cell boundary is off by whole cells), the same state,
validity and needs, and positions equal up to float64 rounding of two orders of evaluating the bicubic
(row first or column first; 1e-9 source pixels on values of at most 1e3, then rounded to float32)."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from lenslab.warp.lattice import lattice_eval, lattice_rows


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), step=st.sampled_from([1, 2, 3, 4, 7, 8, 16]),
       width=st.integers(1, 70), height=st.integers(1, 20), samples=st.integers(1, 4),
       r0=st.integers(0, 5))
def test_row_kernel_matches_the_per_sample_kernel(seed, step, width, height, samples, r0):
    rng = np.random.default_rng(seed)
    ncx = -(-width // step)
    ncy = -(-(height + r0) // step)
    state = rng.choice(np.array([-1, 0, 1, 1, 1, 2], np.int8), size=(ncy, ncx))
    coef = rng.uniform(-1e3, 1e3, size=(ncy, ncx, 5, 4, 4)) * np.outer(0.25 ** np.arange(4), 0.25 ** np.arange(4))
    offs = rng.uniform(0, 1, size=(1, 1, samples, 2))
    offs[0, 0, 0] = [0.5, 0.5]  # a pixel centre: lands exactly on cell boundaries when step divides
    shape = (height, width, samples)
    out = []
    for fn, arg in ((lattice_rows, 1.0 / step), (lattice_eval, float(step))):
        xs, ys = np.full(shape, np.nan, np.float32), np.full(shape, np.nan, np.float32)
        valid, need = np.zeros(shape, bool), np.full(shape, -9, np.int8)
        dirs = np.full(shape + (3,), np.nan)
        fn(coef, state, 0, arg, r0, offs, xs, ys, valid, need, dirs)
        out.append((xs, ys, valid, need, dirs))
    (xa, ya, va, na, da), (xb, yb, vb, nb, db) = out
    np.testing.assert_array_equal(va, vb)
    np.testing.assert_array_equal(na, nb)
    np.testing.assert_allclose(xa, xb, rtol=2e-7, atol=1e-4)  # float32 storage of values up to ~4e3
    np.testing.assert_allclose(ya, yb, rtol=2e-7, atol=1e-4)
    proj = na == 2
    np.testing.assert_allclose(da[proj], db[proj], rtol=1e-9, atol=1e-9)
