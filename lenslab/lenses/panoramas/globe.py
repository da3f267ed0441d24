"""The globe: the sphere of directions seen from outside, from a point in front of it (ffmpeg v360's
``perspective`` output)."""

from __future__ import annotations

import numpy as np

from lenslab.lenses.core import v360
from lenslab.lenses.core.base import FLOAT, Lens, Param, ReferencePoint, as_points, clean
from lenslab.lenses.registry import register

#: bisection steps of the inverse: 60 halvings of [0, 1] reach 1e-18, below float64's spacing at 1
STEPS = 60


def _sin_z(r, h):
    """The sine of a point's angle from the nadir at radius ``r`` of the frame, seen from ``h`` radii."""
    with np.errstate(all="ignore"):
        return np.where(r > 0, (h - np.sqrt(1.0 - r * r)) / (h / np.where(r > 0, r, 1.0) + r / h), 0.0)


@register
class Globe(Lens):
    r"""Globe: the sphere of directions seen from outside, forward at the centre (v360's perspective).

    Drawn as ffmpeg v360's ``perspective`` output draws it: forward (``+z``) at the centre, up at the top.

    With ``(s, t) = (2x/W - 1, 1 - 2y/H)`` (each axis over its own side), ``r = sqrt(s^2 + t^2)`` and
    ``h = 1 + distance``, the angle ``z`` from forward has ``sin z = (h - sqrt(1 - r^2)) / (h/r + r/h)``;
    pixels with ``sin^2 z > 1`` (or ``r > 1``) see nothing. ``d = (sin z s/r, sin z t/r, cos z)``.
    The inverse solves that relation for ``r`` by bisection (it rises with ``r``); only the front
    hemisphere (``d_z >= 0``) is drawn. ``distance`` is v360's ``v_fov`` for this projection.
    """

    name = "globe"
    #: a spec and image size the conformance tests run on (round trips, extremes)
    examples = (("globe:distance=2", (8192, 8192)),)
    #: pinned from outside lenslab (the conformance suite checks both ways): the angle from the view axis
    #: by v360's ``perspective_to_xyz`` in float64 at the pixel, forward at the centre and up at the top as
    #: Debian's ffmpeg 5.1 draws it (its output sees these directions within one pixel, 0.09 degree,
    #: of a 4096-pixel equirect source)
    reference_points = (
        ReferencePoint("globe:distance=2", (800, 800), (530.25, 310.75),
                       (0.2220531074575263, 0.15215539225016675, 0.9630893801084374),
                       "ffmpeg libavfilter/vf_v360.c perspective_to_xyz (v_fov=2), float64"),
        ReferencePoint("globe:distance=0.5", (800, 800), (530.25, 310.75),
                       (0.11799840229774683, 0.08085495128655587, 0.9897165523055719),
                       "ffmpeg libavfilter/vf_v360.c perspective_to_xyz (v_fov=0.5), float64"),
    )
    #: (true spec, perturbed start, fitted parameters) a fit recovers exactly, on a 256 x 192 image
    fit_examples = (("globe:distance=2", "globe:distance=1.5", "distance"),)
    summary = "the sphere seen from outside, from in front (v360's perspective output)"
    #: v360 has this projection as an output only (lenslab.warp.compat_v360)
    v360_output = True
    frame_aspect = 1.0
    params = (Param("distance", 180.0, "distance of the eye from the sphere, in radii beyond 1 (v360's v_fov, whose "
                    "default for this projection is 180 in ffmpeg 5.1)",
                    0.0, None, lo_open=True),)

    def pixel_to_dir(self, xy):
        xy = as_points(xy, 2, "pixel coordinates")
        with np.errstate(all="ignore"):
            s = 2.0 * xy[..., 0] / self.width - 1.0
            t = 1.0 - 2.0 * xy[..., 1] / self.height
            r = np.hypot(s, t)
            ok = r <= 1.0 + 1e-12  # the rim's own pixels, within a rounding of their radius
            r = np.minimum(r, 1.0)
            sz = _sin_z(r, 1.0 + self.distance)
            ok &= (sz * sz <= 1.0) & self.in_image(xy)
            cz = np.sqrt(np.maximum(0.0, 1.0 - sz * sz))
            rr = np.where(r > 0, r, 1.0)
            d = np.stack([sz * s / rr, sz * t / rr, cz], axis=-1).astype(FLOAT)
        return clean(d, ok, inplace=True)

    def v360_pixel_to_dir(self, xy):
        """The rays v360 gives this output's pixels: off the sphere (invisible to v360) it samples straight down."""
        xy = as_points(xy, 2, "pixel coordinates")
        d, ok = self.pixel_to_dir(xy)
        return v360.filled(self, xy, d, ok, v360.DOWN)

    def dir_to_pixel(self, dirs):
        d = as_points(dirs, 3, "directions")
        with np.errstate(all="ignore"):
            n = np.sqrt(np.einsum("...i,...i->...", d, d))
            d = d / n[..., None]
            h = 1.0 + self.distance
            sz = np.hypot(d[..., 0], d[..., 1])
            lo, hi = np.zeros(sz.shape), np.ones(sz.shape)
            for _ in range(STEPS):
                mid = 0.5 * (lo + hi)
                below = _sin_z(mid, h) < sz
                lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
            r = 0.5 * (lo + hi)
            # the rim's own directions come back within a rounding of its sine
            ok = (n > 0) & np.isfinite(n) & (d[..., 2] >= 0) & (sz <= _sin_z(np.ones(1), h)[0] * (1.0 + 1e-12))
            k = np.where(sz > 0, r / np.where(sz > 0, sz, 1.0), 0.0)
            xy = np.stack([(d[..., 0] * k + 1.0) * 0.5 * self.width, (1.0 - d[..., 1] * k) * 0.5 * self.height], -1)
            ok &= self.snap_to_image(xy)
        return clean(xy, ok, inplace=True)
