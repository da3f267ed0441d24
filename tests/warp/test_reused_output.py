"""An output reused from frame to frame (``WarpPlan.run(into=...)``, as a clip's frames are warped) is not zeroed
when the plan keeps its maps as taps, which set every pixel: what an earlier frame or garbage left there must not
show. Checked against analytic values: a uniform source of radiance 2 seen through a
180-degree fisheye is 2 inside the image circle (alpha 1) and 0 outside (alpha 0)."""

from __future__ import annotations

import numpy as np

from lenslab.lenses import Camera
from lenslab.warp.batch import PlanCache
from lenslab.warp.taps import TapBand


def test_a_reused_output_holds_only_this_frames_pixels():
    src, dst = Camera.from_spec("equirect", (128, 64)), Camera.from_spec("fisheye:fov=180", (40, 40))
    cache = PlanCache()
    pano = np.full((64, 128, 3), 2.0, np.float32)
    cache.warp_frame(pano, src, dst)  # the first frame: the plan keeps its maps as taps
    assert all(isinstance(b, TapBand) for b in cache.plan(src, dst)._bands)
    into = (np.full((40, 40, 3), np.nan, np.float32), np.full((40, 40), 7.0, np.float32))
    out, alpha = cache.warp_frame(pano, src, dst, into=into)
    assert out is into[0] and alpha is into[1]
    y, x = np.mgrid[0:40, 0:40] + 0.5
    r = np.hypot(x - 20, y - 20) / 20  # the image circle has radius 1 in these units
    inside, outside = r < 0.97, r > 1.03  # away from the rim, where a pixel is partly covered
    assert (alpha[inside] == 1).all() and (alpha[outside] == 0).all()
    assert (out[inside] == 2).all() and (out[outside] == 0).all()
    assert np.isfinite(out).all() and set(np.unique(alpha)) <= {0.0, 1.0}
