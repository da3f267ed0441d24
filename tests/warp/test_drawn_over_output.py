"""A still image's warp draws straight over the memory it writes (``WarpPlan.run(into=...)`` with the colour and
alpha channels of one RGBA image, :func:`lenslab.io.alpha.room_for_alpha`): a plain map's bands set every pixel
(the sampler writes 0 where no sample is valid), so that memory is neither zeroed first nor copied into each
band's scratch rows. What was there (garbage: NaN, 7) must not show. Checked against analytic values: a uniform
source of radiance 2 seen through a 180-degree fisheye is 2 inside the image circle (alpha 1), 0 outside
(alpha 0); the pixels within 3 % of the rim are partly covered and not checked.
"""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.lenses import Camera
from lenslab.warp.batch import PlanCache


class Watched(np.ndarray):
    """An array that records the fills asked of it (and of its views)."""

    fills: list = []

    def fill(self, value):
        Watched.fills.append(value)
        super().fill(value)


@pytest.mark.parametrize("filter", ["bilinear", "bicubic"])
@pytest.mark.parametrize("samples", [1, 4])
def test_a_plain_map_draws_every_pixel_over_garbage_without_zeroing(filter, samples):
    src, dst = Camera.from_spec("equirect", (128, 64)), Camera.from_spec("fisheye:fov=180", (40, 40))
    cache = PlanCache(filter=filter, samples=samples, max_map_bytes=0, band_points=400)  # maps not kept
    pano = np.full((64, 128, 3), 2.0, np.float32)
    image = np.full((40, 40, 4), np.nan, np.float32).view(Watched)
    image[..., 3] = 7.0
    Watched.fills = []
    into = (image[..., :3], image[..., 3])
    out, alpha = cache.warp_frame(pano, src, dst, into=into)
    assert out is into[0] and alpha is into[1]  # drawn into the RGBA image's channels...
    assert Watched.fills == []  # ...over what was there, not zeroed first
    assert cache.plan(src, dst)._bands is None  # the uncached path: scratch bands copied into the strided rows
    y, x = np.mgrid[0:40, 0:40] + 0.5
    r = np.hypot(x - 20, y - 20) / 20  # the image circle has radius 1 in these units
    inside, outside = r < 0.97, r > 1.03
    assert (alpha[inside] == 1).all() and (alpha[outside] == 0).all()
    np.testing.assert_allclose(out[inside], 2.0, rtol=0, atol=1e-6)  # (bicubic's weights sum to 1 in float64)
    assert (out[outside] == 0).all()
    assert np.isfinite(image).all() and (image[..., 3] >= 0).all() and (image[..., 3] <= 1).all()


def test_an_antialiased_warp_still_zeroes_what_it_may_leave():
    src, dst = Camera.from_spec("equirect", (128, 64)), Camera.from_spec("fisheye:fov=180", (40, 40))
    cache = PlanCache(antialias=True, max_map_bytes=0)
    image = np.full((40, 40, 4), np.nan, np.float32).view(Watched)
    Watched.fills = []
    out, alpha = cache.warp_frame(np.full((64, 128, 3), 2.0, np.float32), src, dst,
                                  into=(image[..., :3], image[..., 3]))
    assert Watched.fills == [0.0, 0.0]
    assert np.isfinite(image).all()
