"""The ball: the whole sphere as a mirror ball photographed from the front (ffmpeg v360's ``ball``)."""

from __future__ import annotations

import numpy as np

from lenslab.lenses.core import v360
from lenslab.lenses.core.base import FLOAT, Lens, ReferencePoint
from lenslab.lenses.registry import register


@register
class Ball(Lens):
    r"""Mirror ball: the whole sphere in a circle, the front (+z) at the centre, the back pole at the rim.

    With ``(s, t) = (2x/W - 1, 1 - 2y/H)`` (each axis spans its own side: on a square frame the ball is
    a circle) and ``r = sqrt(s^2 + t^2) <= 1``, the angle from the axis is ``a = 2 asin(r)``:
    ``d = (sin a s/r, sin a t/r, cos a)``, the equisolid (Lambert equal-area) fisheye of the whole
    sphere. Inverse: ``r = sin(a/2) = sqrt((1 - d_z) / 2)``. v360's ``ball``; on square frames the same
    as ``fisheye:fov=360,mapping=equisolid``.
    """

    name = "ball"
    #: a spec and image size the conformance tests run on (round trips, extremes)
    examples = (("ball", (8192, 8192)),)
    #: pinned from outside lenslab (the conformance suite checks both ways): v360's ``xyz_to_ball`` in
    #: float64, in its frame (y down), its frame coordinates taken as lenslab's continuous pixel
    reference_points = (
        ReferencePoint("ball", (800, 600), (703.4784055646675, 163.43471749589963),
                       (0.7071067811865475, 0.42426406871192845, -0.565685424949238),
                       "ffmpeg libavfilter/vf_v360.c xyz_to_ball, float64"),
    )
    summary = "mirror ball: the whole sphere in a circle, front at the centre, back pole at the rim"
    #: how ffmpeg's v360 reads this projection as its input (lenslab.warp.compat_v360)
    v360_read = "span"
    #: the frame the model fills, width / height (the default output size of lenslab warp)
    frame_aspect = 1.0

    def uv_to_dir(self, uv):
        s, t = uv[..., 0], uv[..., 1] / self.aspect
        r = np.hypot(s, t)
        ok = r <= 1.0 + 1e-12  # the rim's own pixels, within a rounding of their radius
        r = np.minimum(r, 1.0)
        a = 2.0 * np.arcsin(r)
        k = np.where(r > 0, np.sin(a) / np.where(r > 0, r, 1.0), 2.0)  # sin(2 asin r) / r -> 2 at r = 0
        d = np.empty(uv.shape[:-1] + (3,), dtype=FLOAT)
        d[..., 0] = k * s
        d[..., 1] = k * t
        d[..., 2] = np.cos(a)
        return d, ok

    def v360_pixel_to_dir(self, xy):
        """The rays v360 gives this output's pixels: outside the circle (invisible to v360) it samples straight down."""
        return v360.continued(self, xy, self.uv_to_dir, v360.DOWN)

    def dir_to_uv(self, d):
        r = np.sqrt(np.maximum(0.0, 1.0 - np.clip(d[..., 2], -1.0, 1.0)) * 0.5)
        lat = np.hypot(d[..., 0], d[..., 1])
        uv = np.empty(d.shape[:-1] + (2,), dtype=FLOAT)
        # straight back: every point of the rim; take its rightmost point
        cs = np.where(lat > 0, d[..., 0] / np.where(lat > 0, lat, 1.0), 1.0)
        sn = np.where(lat > 0, d[..., 1] / np.where(lat > 0, lat, 1.0), 0.0)
        uv[..., 0] = r * cs
        uv[..., 1] = r * sn * self.aspect
        return uv, np.ones(d.shape[:-1], dtype=bool)
