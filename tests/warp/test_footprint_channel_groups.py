"""The footprint filter on images of 2 or 5 channels (a luminance with alpha, a multispectral stack): the kernel
integrates them in groups of at most four channels, each group from its own rows' prefix sums, and is held to
the NumPy reference (lenslab.warp.kernels.reference.footprint), which takes all channels at once."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.warp.pyramid import pyramid
from lenslab.warp.seam import Border


@pytest.mark.parametrize("nc", [2, 5])
def test_footprint_filter_of_other_channel_counts_matches_the_reference(nc):
    """Images of 2 or 5 channels run the filter in groups of at most four channels (the rows' prefix sums of
    each group): against the NumPy reference, to the float64 rounding (2 float32 ulp)."""
    from lenslab import cxx_kernels as K
    from lenslab.warp.kernels import reference as ref
    from lenslab.warp.pyramid import MAX_TAPS

    rng = np.random.default_rng(nc)
    img = rng.uniform(0.0, 1.0, (32, 64, nc)).astype(np.float32)
    pyr = pyramid(img, Border(True, True, True))
    n = 300
    x = rng.uniform(-0.5, 63.5, (n, 1)).astype(np.float32)
    y = rng.uniform(-0.5, 31.5, (n, 1)).astype(np.float32)
    size = np.exp(rng.uniform(np.log(0.1), np.log(12.0), n))
    theta = rng.uniform(0.0, np.pi, n)
    foot = np.stack([np.cos(theta) * size, np.sin(theta) * size, -np.sin(theta) * size / 2,
                     np.cos(theta) * size / 2], axis=-1).astype(np.float32).reshape(n, 1, 4)
    out, alpha = np.empty((n, nc), np.float32), np.empty(n, np.float32)
    K.footprint(pyr.level0, pyr.rest, pyr.shapes, pyr.offsets, x, y, np.ones((n, 1), bool), foot, True, True, True,
                MAX_TAPS, out, alpha)
    want, _ = ref.footprint(pyr, x, y, np.ones((n, 1), bool), foot, (True, True, True))
    eps = float(np.finfo(np.float32).eps)
    np.testing.assert_allclose(out, want, rtol=2 * eps, atol=2 * eps)
