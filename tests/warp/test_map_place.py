"""``place``: the compiled pass that writes the samples a lattice left (mapped exactly or projected) into a band's
maps, against NumPy's assignments (the reference) and pinned values; positions beyond the maps are refused."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.warp.kernels import lattice_reference as ref
from lenslab.warp.lattice import place


def test_place_writes_index_coordinates_where_valid_and_zero_elsewhere():
    xs, ys, valid = np.full(6, 7.0, np.float32), np.full(6, 7.0, np.float32), np.zeros(6, bool)
    # pixel (10.5, 3.25) is index (10, 2.75); an invalid sample is 0 whatever its position; 4096 + 2^-20 - 0.5
    # rounds to the float32 nearest 4095.5 (float32 holds 2^-12 there)
    xy = np.array([[10.5, 3.25], [1e30, -1e30], [4096.0 + 2.0**-20, np.nan]])
    place(np.array([4, 0, 2]), xy, np.array([True, False, True]), xs, ys, valid)
    assert xs.tolist() == [0.0, 7.0, 4095.5, 7.0, 10.0, 7.0]
    assert ys[[4, 0]].tolist() == [2.75, 0.0] and np.isnan(ys[2])
    assert valid.tolist() == [False, False, True, False, True, False]


def test_place_matches_numpys_assignments():
    rng = np.random.default_rng(2)
    n, size = 5000, 20000
    at = rng.choice(size, n, replace=False)
    xy = rng.uniform(-5000.0, 5000.0, (n, 2)) * np.exp(rng.uniform(-30, 30, (n, 1)))
    v = rng.uniform(size=n) > 0.3
    got = [np.zeros(size, np.float32), np.zeros(size, np.float32), np.zeros(size, bool)]
    want = [a.copy() for a in got]
    place(at, xy, v, *got)
    ref.place(at, xy, v, *want)
    for g, w in zip(got, want):
        np.testing.assert_array_equal(g, w)


@pytest.mark.parametrize("bad", [-1, 10])
def test_place_refuses_a_position_beyond_the_maps(bad):
    maps = (np.zeros(10, np.float32), np.zeros(10, np.float32), np.zeros(10, bool))
    with pytest.raises(ValueError, match="beyond the maps"):
        place(np.array([bad]), np.zeros((1, 2)), np.ones(1, bool), *maps)
