"""The single-sample bilinear kernel says what it wrote (some value not finite, some sample covered), so the
warp checks its rows without a second pass over them. Its word must be what a scan of the rows finds:
NumPy's ``isfinite`` and ``any`` over the written arrays are the oracle, on sources holding NaN, infinities
and values near float32's largest, whose lerps overflow."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from lenslab import cxx_kernels as K
from lenslab.lenses import Camera
from lenslab.warp import warp
from lenslab.warp.checks import OutputChecks
from lenslab.warp.filters import SAMPLED_COVERED, SAMPLED_NON_FINITE, sample
from lenslab.warp.seam import Border

BIG = float(np.finfo(np.float32).max)


def _scan(out: np.ndarray, alpha: np.ndarray) -> int:
    return (0 if np.isfinite(out).all() else SAMPLED_NON_FINITE) | (SAMPLED_COVERED if alpha.any() else 0)


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), nc=st.sampled_from([1, 3, 4, 5]), bad=st.sampled_from(
    [None, np.nan, np.inf, -np.inf, BIG]), share=st.sampled_from([0.0, 0.01, 0.5, 1.0]))
def test_the_kernels_word_is_what_a_scan_of_its_rows_finds(seed, nc, bad, share):
    rng = np.random.default_rng(seed)
    h, w, n = 9, 13, 400
    src = rng.uniform(-2.0, 2.0, (h, w, nc)).astype(np.float32)
    if bad is not None:  # a few texels NaN, infinite, or so large that a lerp with a negative one overflows
        src.reshape(-1)[rng.integers(0, src.size, 3)] = bad
        if bad == BIG:
            src.reshape(-1)[rng.integers(0, src.size, 3)] = -BIG
    xs = rng.uniform(-1.0, w, n).astype(np.float32)
    ys = rng.uniform(-1.0, h, n).astype(np.float32)
    valid = rng.uniform(size=n) < share
    out = np.full((n, nc), 7.0, np.float32)
    alpha = np.full(n, 7.0, np.float32)
    said = K.bilinear1(src.reshape(-1), w, h, nc, xs, ys, valid, *Border(True, True, True).flags, out, alpha)
    assert said == _scan(out, alpha)
    assert set(np.unique(alpha)) <= {0.0, 1.0}  # coverage in range by construction: nothing to scan


def test_the_other_kernels_leave_the_rows_to_the_scan():
    src = np.ones((4, 4, 3), np.float32)
    xs = ys = np.full((2, 2, 4), 1.5, np.float32)
    out, alpha = np.zeros((2, 2, 3), np.float32), np.zeros((2, 2), np.float32)
    assert sample(src, xs, ys, np.ones((2, 2, 4), bool), Border(), "bilinear", out, alpha) is None  # 4 samples
    assert sample(src, xs[..., :1], ys[..., :1], np.ones((2, 2, 1), bool), Border(), "bicubic", out, alpha) is None


def test_checks_take_the_word_and_still_scan_an_images_own_alpha():
    out = np.zeros((2, 3, 4), np.float32)
    out[0, 0, 3] = 1.5  # the image's own alpha out of range: only a scan finds it
    checks = OutputChecks(image_alpha=True)
    checks.band(out, np.ones((2, 3), np.float32), slice(0, 2), SAMPLED_COVERED)
    assert checks.finite and checks.covered and not checks.in_range
    plain = OutputChecks(image_alpha=False)
    plain.band(out[..., :3], np.zeros((2, 3), np.float32), slice(0, 2), SAMPLED_NON_FINITE)
    assert not plain.finite and not plain.covered and plain.in_range


@pytest.mark.parametrize("value", [BIG, -BIG])
def test_an_overflowing_warp_is_still_found_and_clamped(value):
    """Taps of +-float32 max next to opposite ones: the float32 lerp passes the range, the kernel re-does it in
    float64 (never inf); a NaN-free, finite output either way, as a scan says."""
    src = np.full((32, 64, 3), value, np.float32)
    src[:, ::2] = -value
    image, alpha = warp(src, Camera.from_spec("equirect", (64, 32)), Camera.from_spec("fisheye:fov=180", (24, 24)))
    assert np.isfinite(image).all() and alpha.max() == 1.0
