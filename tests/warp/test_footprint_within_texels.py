"""The footprint filter never leaves the range of the texels it read (``src/native/footprint_runs.cpp``: each
footprint's mean is kept within the least and greatest texel of its run's shared window).

The exact box average of a bilinear reconstruction is a convex combination of the texels read, so a non-negative
source gives non-negative values. Before, float64 rounding of the rows' prefix sums made small negatives: where a
source is 0 right of a bright step, a run's prefix sums carry the step's sum as a constant along the zero texels,
and the contour integral of that constant cancels only to rounding (here down to -4e-11 beside texels of 3.4e4).

Outside values: the source is B left of column 50 and 0 from it on, constant in y. A footprint whose corners all lie
at x <= 49 or all at x >= 50 sees a constant reconstruction, and its exact mean is B or 0 (the filter's quadrature
is exact there: F is linear along every edge). Those are held to B and 0 to float64 rounding; the footprints
across the ramp between the texels 49 and 50 (where 2-point Gauss-Legendre along an edge that crosses a texel
column is not exact) are held to the NumPy reference, which reads each footprint through its own window.
"""

from __future__ import annotations

import numpy as np
import pytest

from lenslab import cxx_kernels as K
from lenslab.warp.kernels import footprint_reference as fref
from lenslab.warp.pyramid import MAX_TAPS, pyramid
from lenslab.warp.seam import Border

EPS32 = float(np.finfo(np.float32).eps)
PANO = Border(True, True, True)
B = 3.4e4  # a sun's texels
STEP = 50  # the first zero column


@pytest.mark.parametrize("nc", [1, 3])
@pytest.mark.parametrize("a, b", [((2.6, 0.4), (-0.3, 2.2)), ((1.7, -0.3), (0.4, 1.9)), ((3.1, 0.2), (0.5, 2.4))])
def test_a_step_on_zero_gives_its_exact_mean_and_no_negative(nc, a, b):
    src = np.zeros((64, 128, nc), np.float32)
    src[:, :STEP] = B
    pyr = pyramid(src, PANO)
    # rows of pixels on an affine map, their footprints the exact preimages (neighbours' sides coincide), across
    # the step: runs whose shared window holds both the bright texels and the zero ones
    r, p = np.mgrid[0:14, 0:30].astype(np.float64)
    xs = (30.3 + a[0] * p + b[0] * r).astype(np.float32)
    ys = (12.1 + a[1] * p + b[1] * r).astype(np.float32)
    foot = np.ascontiguousarray(np.broadcast_to(np.array([*a, *b], np.float32), (14, 30, 1, 4)))
    out = np.empty((14, 30, nc), np.float32)
    alpha = np.empty((14, 30), np.float32)
    K.footprint(pyr.level0, pyr.rest, pyr.shapes, pyr.offsets, xs[..., None], ys[..., None],
                np.ones((14, 30, 1), bool), foot, *PANO.flags, MAX_TAPS, out, alpha)
    assert (alpha == 1.0).all()
    assert (out >= 0.0).all()  # (before: 111 values down to -4e-11 for the first a, b on 3 channels)
    assert (out <= B).all()
    cx = xs.astype(np.float64)
    corners = np.stack([cx + sa * a[0] + sb * b[0] for sa in (-0.5, 0.5) for sb in (-0.5, 0.5)])
    bright = (corners <= STEP - 1).all(axis=0) & (corners >= 1).all(axis=0)  # (away from the seam: column 127 is 0)
    dark = (corners >= STEP).all(axis=0) & (corners <= 126).all(axis=0)
    assert bright.sum() > 30 and dark.sum() > 30
    # float64 throughout but the prefix sums' rounding (each sums at most 64 texels of B along a row: below
    # 64 * 2^-53 * 64 B = 4.5e-13 B for each of a footprint's few Gauss points, over an area above 3 texels), and
    # one float32 rounding of the result
    assert (np.abs(out[bright] - B) <= 2 * EPS32 * B).all()
    assert (out[dark] <= 1e-12 * B).all()
    across = ~(bright | dark)
    ref, _ = fref.footprint(pyr, xs[..., None], ys[..., None], np.ones((14, 30, 1), bool), foot, PANO.flags)
    np.testing.assert_allclose(out[across], ref.reshape(out.shape)[across], rtol=2 * EPS32, atol=1e-12 * B)
