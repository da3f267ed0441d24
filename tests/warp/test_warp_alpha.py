"""Alpha is coverage: the fraction of each output pixel's samples that land on the source."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.lenses import Camera
from lenslab.warp import warp


def frustum_coverage(dst: Camera, samples: int) -> np.ndarray:
    """Fraction of each pixel's strata-centre rays inside a 90-degree square frustum looking along +z."""
    _, d, v = dst.rays(samples=samples, seed=None)
    z = np.where(d[..., 2] > 0, d[..., 2], 1.0)
    inside = v & (d[..., 2] > 0) & (np.abs(d[..., 0] / z) <= 1) & (np.abs(d[..., 1] / z) <= 1)
    return inside.mean(axis=2)


@pytest.mark.parametrize("exact", [False, True])
def test_perspective_into_fisheye_ring(exact):
    src = Camera.from_spec("perspective:fov=90", (64, 64))
    dst = Camera.from_spec("fisheye:fov=180", (128, 128))
    colour = np.array([2.5, 0.5, 7.0], np.float32)  # HDR, so a clamp would show
    img = np.broadcast_to(colour, (64, 64, 3)).copy()
    out, alpha = warp(img, src, dst, samples=16, exact_map=exact)
    expect = frustum_coverage(dst, 16)
    inside, outside = expect == 1, expect == 0
    ring = ~inside & ~outside
    assert inside.sum() > 1000 and outside.sum() > 5000 and ring.sum() > 100
    np.testing.assert_array_equal(alpha[inside], 1.0)
    np.testing.assert_array_equal(alpha[outside], 0.0)
    np.testing.assert_array_equal(out[outside], 0.0)
    # partial in the ring, in steps of 1/16; a sample within ~1e-9 of the frustum's edge may fall on
    # either side, so allow one step on a handful of ring pixels
    assert np.all((alpha[ring] > 0) & (alpha[ring] < 1))
    diff = np.abs(alpha - expect)
    assert np.all(diff <= 1 / 16 + 1e-7) and np.count_nonzero(diff) <= 0.02 * ring.sum()
    # premultiplied: a constant colour comes out as colour x alpha
    np.testing.assert_allclose(out, colour * alpha[..., None], rtol=2e-7, atol=0)


def test_fisheye_corners_are_zero_never_nan():
    src = Camera.from_spec("equirect", (128, 64))
    dst = Camera.from_spec("fisheye:fov=180", (64, 48))
    img = np.full((64, 128, 3), np.inf, np.float32)  # even infinite input gives no NaN
    img[:, :, 1] = np.nan
    with pytest.warns(RuntimeWarning, match="non-finite"):
        out, alpha = warp(img, src, dst, filter="lanczos", samples=4)
    assert not np.isnan(out).any() and not np.isnan(alpha).any()
    _, _, v = dst.rays(samples=4, seed=None)
    np.testing.assert_array_equal(alpha, v.mean(axis=2).astype(np.float32))
    assert np.all(out[alpha == 0] == 0)
    assert np.all(out[alpha > 0][:, 1] == 0)  # NaN reads as 0


def test_antialias_alpha_is_partial_at_the_rim():
    src = Camera.from_spec("equirect", (256, 128))
    dst = Camera.from_spec("fisheye:fov=180", (64, 64))
    img = np.ones((128, 256, 3), np.float32)
    out, alpha = warp(img, src, dst, antialias=True)
    cover = dst.rays(samples=64, seed=None)[2].mean(axis=2)
    # rim pixels are split into 4x4 sub-samples: coverage within 1/16 of the 8x8 count (plus the
    # stratum-edge effect of one sample: 1/8)
    assert np.abs(alpha - cover).max() <= 0.13
    assert ((alpha > 0) & (alpha < 1)).sum() > 50
    np.testing.assert_allclose(out[..., 0], alpha, rtol=1e-6, atol=1e-6)  # constant 1, premultiplied
