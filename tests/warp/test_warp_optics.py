"""Per-channel lenses (chromatic aberration) and falloff (vignetting) in the warp engine, with a tiny test
lens defined here: each output channel must hold the value its own channel lens's ray reads, computed
from the perspective and equirect formulas of docs/conventions.md transcribed in float64 below."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.lenses import Camera, Lens
from lenslab.lenses.projections.perspective import Perspective
from lenslab.warp import WarpPlan, warp

FOVS = (50.0, 56.0, 62.0)  # horizontal field of view of the R, G, B channel lenses, degrees
W, H = 40, 30  # the test lens's image
SW, SH = 256, 128  # the equirect source


class Tinted(Perspective):
    """A perspective lens (the G geometry) whose R and B pictures have other fields of view, dimmed
    by ``1 - 0.3 r^2`` with ``r`` the distance from the centre in units of half the width."""

    name = ""  # a test lens: not registered

    def channel_lenses(self):
        return tuple(Perspective(self.width, self.height, fov=f) for f in FOVS)

    def falloff(self, xy):
        xy = np.asarray(xy, dtype=np.float64)
        return falloff(xy[..., 0], xy[..., 1])


def falloff(x, y):
    return 1.0 - 0.3 * ((x - W / 2) ** 2 + (y - H / 2) ** 2) / (W / 2) ** 2


def tinted() -> Lens:
    return Tinted(W, H, fov=FOVS[1])


def perspective_rays(fov: float) -> np.ndarray:
    """Rays of a W x H perspective's pixel centres: (u, v, 1 / tan(fov/2)), u = 2x/W - 1, v = (1 - 2y/H) H/W."""
    y, x = np.mgrid[0:H, 0:W] + 0.5
    return np.stack([2 * x / W - 1, (1 - 2 * y / H) * H / W, np.full(x.shape, 1 / np.tan(np.radians(fov) / 2))], -1)


def ramp_source() -> np.ndarray:
    """An equirect source whose every channel holds its column index (linear: bilinear reads it exactly)."""
    return np.broadcast_to(np.arange(SW, dtype=np.float32)[None, :, None], (SH, SW, 3)).copy()


def ramp_value(d: np.ndarray) -> np.ndarray:
    """The ramp read along rays ``d``: the equirect column x = (atan2(dx, dz)/pi + 1) W/2, index x - 1/2."""
    return (np.arctan2(d[..., 0], d[..., 2]) / np.pi + 1) * SW / 2 - 0.5


@pytest.mark.parametrize("how", ["one-shot", "cached", "antialias"])
def test_each_output_channel_takes_its_own_channel_lens_s_ray_times_the_falloff(how):
    src = Camera.from_spec("equirect", (SW, SH))
    dst = Camera(tinted())
    plan = WarpPlan(src, dst, cache=how == "cached", antialias=how == "antialias")
    out, alpha = plan.run(ramp_source())
    if how == "cached":
        out, alpha = plan.run(ramp_source())  # the second run reads the kept maps
        assert plan.map_bytes > 0
    assert alpha.min() == 1.0
    y, x = np.mgrid[0:H, 0:W] + 0.5
    for c, fov in enumerate(FOVS):
        want = ramp_value(perspective_rays(fov)) * falloff(x, y)
        # bilinear reads a linear ramp exactly; float32 maps resolve 1e-4 px at 256 px; the footprint
        # average of a linear function is its value at the footprint's centre, to the same precision
        np.testing.assert_allclose(out[..., c], want, atol=2e-3)
    # the channels really differ: R and B are several columns from G at the image's edge
    assert np.abs(out[..., 0] - out[..., 1]).max() > 1.0


def test_each_source_channel_is_read_at_its_own_channel_lens_and_divided_by_the_falloff():
    src = Camera(tinted())
    dst = Camera.from_spec("perspective:fov=40", (24, 18))
    img = np.broadcast_to(np.arange(W, dtype=np.float32)[None, :, None], (H, W, 3)).copy()
    out, alpha = warp(img, src, dst)
    assert alpha.min() == 1.0
    # the output's rays, by the perspective formula (40 degrees, 24 x 18)
    y, x = np.mgrid[0:18, 0:24] + 0.5
    d = np.stack([2 * x / 24 - 1, (1 - 2 * y / 18) * 18 / 24, np.full(x.shape, 1 / np.tan(np.radians(20)))], -1)
    for c, fov in enumerate(FOVS):
        # where channel lens c sees the ray: x = (dx/dz / tan(fov/2) + 1) W/2, y = (1 - dy/dz / tan(fov/2) W/H) H/2
        t = np.tan(np.radians(fov) / 2)
        qx = (d[..., 0] / d[..., 2] / t + 1) * W / 2
        qy = (1 - d[..., 1] / d[..., 2] / t * W / H) * H / 2
        # the source divided by its falloff at each pixel centre, read bilinearly: exact for the product's
        # linear part; the curvature of 1/falloff over one pixel bounds the rest (<1e-3 relative here)
        want = (qx - 0.5) / falloff(qx, qy)
        np.testing.assert_allclose(out[..., c], want, rtol=2e-3)


def test_a_grey_image_follows_the_green_lens_alone():
    src = Camera.from_spec("equirect", (SW, SH))
    out, alpha = warp(ramp_source()[..., :1], src, Camera(tinted()))
    y, x = np.mgrid[0:H, 0:W] + 0.5
    np.testing.assert_allclose(out[..., 0], ramp_value(perspective_rays(FOVS[1])) * falloff(x, y), atol=2e-3)
