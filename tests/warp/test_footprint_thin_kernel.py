"""The compiled test for slivers (``thin_footprints`` in ``src/native/lattice.cpp``) picks the footprints that
:func:`lenslab.warp.antialias.thicken_slivers` widens exactly as NumPy's float32 steps do
(:func:`lenslab.warp.antialias.thin_reference`), NaN, inf and the threshold's own rounding included.

Outside value: a footprint whose height across its longer side is written out in float64 here, far from the
threshold, is thin exactly when that height is below min(SLIVER_HEIGHT, longer side / SLIVER_ANISOTROPY).
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings, strategies as st

from lenslab.warp.antialias import SLIVER_ANISOTROPY, SLIVER_HEIGHT, thin_reference
from lenslab.warp.kernels import native


def _thin(foot):
    flat = np.ascontiguousarray(foot, np.float32).reshape(-1, 4)
    idx = np.empty(len(flat), np.int64)
    n = native.kernels().thin_footprints(flat, np.float32(SLIVER_HEIGHT ** 2), np.float32(SLIVER_ANISOTROPY ** 2), idx)
    return idx[:n]


side = st.one_of(st.floats(-64.0, 64.0, width=32), st.sampled_from([0.0, -0.0, np.nan, np.inf, -np.inf, 1e-30, 3e38]))


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(side, side, side, side), min_size=1, max_size=40))
def test_the_compiled_test_is_numpys(feet):
    foot = np.array(feet, np.float32)
    with np.errstate(invalid="ignore", over="ignore"):  # (inf - inf, 3e38 squared: NaN and inf, as meant)
        want = thin_reference(foot)
    np.testing.assert_array_equal(_thin(foot), want)


def test_heights_written_out():
    rng = np.random.default_rng(5)
    n = 4000
    length = rng.uniform(0.2, 12.0, n)
    angle = rng.uniform(0.0, 2 * math.pi, n)
    limit = np.minimum(SLIVER_HEIGHT, length / SLIVER_ANISOTROPY)
    height = limit * np.where(rng.random(n) < 0.5, rng.uniform(0.1, 0.9, n), rng.uniform(1.1, 4.0, n))
    shear = rng.uniform(-0.4, 0.4, n) * height  # b's part along a: the height is unchanged
    a = np.stack([length * np.cos(angle), length * np.sin(angle)], axis=1)
    normal = np.stack([-np.sin(angle), np.cos(angle)], axis=1)
    b = normal * height[:, None] + a / length[:, None] * shear[:, None]
    foot = np.concatenate([a, b], axis=1).astype(np.float32)
    np.testing.assert_array_equal(_thin(foot), np.flatnonzero(height < limit))
