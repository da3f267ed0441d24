"""The tetrahedral map: the sphere projected onto a regular tetrahedron, unfolded onto a 1:1 frame
(ffmpeg v360's ``tetrahedron``)."""

from __future__ import annotations

import numpy as np

from lenslab.lenses.core.base import FLOAT, Lens, ReferencePoint
from lenslab.lenses.registry import register

@register
class Tetrahedron(Lens):
    r"""Tetrahedral map: the sphere projected onto a tetrahedron, unfolded onto a square.

    As v360's ``tetrahedron`` draws it: in v360's frame ``v = (d_x, -d_y, d_z)`` (``y``
    down) the tetrahedron has its corners along ``(1, 1, -1)``, ``(-1, -1, -1)``, ``(1, -1, 1)`` and
    ``(-1, 1, 1)``; a direction is scaled onto its surface, ``p = v / max_k (v . n_k)``. With
    ``(x, y, z) = (p_x, p_y, -p_z)``, the row is ``y/H = (1 - y)/2`` and the column ``x/W = (x + 1)/4`` where
    ``x + y >= 0, y + z >= 0, z + x >= 0`` or ``x + y <= 0, z - y >= 0, z - x >= 0`` (the left half), else
    ``x/W = (3 - x)/4`` (the right half). Inverse, with ``(a, b)`` the pixel over the frame's size:
    ``p = (4a - 1 or 3 - 4a, 1 - 2b, 2 |1 - |1 - 2a + b|| - 1)``, then ``d = (p_x, -p_y, p_z) / |p|``.
    The top and bottom edges fold onto themselves.
    """

    name = "tetrahedron"
    #: a spec and image size the conformance tests run on (round trips, extremes)
    examples = (("tetrahedron", (8192, 8192)),)
    #: pinned from outside lenslab (the conformance suite checks both ways): v360's ``xyz_to_tetrahedron``
    #: in float64 (frame fractions times the size), a point on each half of the frame
    reference_points = (
        ReferencePoint("tetrahedron", (800, 800), (529.4117647058823, 188.23529411764704),
                       (0.3391400513665329, -0.5087100770497993, 0.79132678652191),
                       "ffmpeg libavfilter/vf_v360.c xyz_to_tetrahedron, float64"),
        ReferencePoint("tetrahedron", (800, 800), (107.69230769230771, 461.5384615384615),
                       (-0.7442084075352507, 0.24806946917841693, -0.6201736729460423),
                       "ffmpeg libavfilter/vf_v360.c xyz_to_tetrahedron, float64"),
    )
    summary = "tetrahedral map: the sphere on a tetrahedron, unfolded onto a square"
    #: how ffmpeg's v360 reads this projection as its input (lenslab.warp.compat_v360)
    v360_read = "shift"
    frame_aspect = 1.0

    def pixel_to_dir(self, xy):
        from lenslab.lenses.core.base import as_points, clean

        xy = as_points(xy, 2, "pixel coordinates")
        with np.errstate(all="ignore"):
            uf, vf = xy[..., 0] / self.width, xy[..., 1] / self.height
            v = np.empty(xy.shape[:-1] + (3,), dtype=FLOAT)
            v[..., 0] = np.where(uf < 0.5, 4.0 * uf - 1.0, 3.0 - 4.0 * uf)
            v[..., 1] = 1.0 - 2.0 * vf
            v[..., 2] = 2.0 * np.abs(1.0 - np.abs(1.0 - 2.0 * uf + vf)) - 1.0
            d = v * FRAME_SIGN
            d /= np.sqrt(np.einsum("...i,...i->...", d, d))[..., None]
            ok = self.in_image(xy)
        return clean(d, ok, inplace=True)

    def dir_to_pixel(self, dirs):
        from lenslab.lenses.core.base import as_points, clean

        d = as_points(dirs, 3, "directions")
        with np.errstate(all="ignore"):
            v = d * FRAME_SIGN
            m = (v @ CORNERS.T).max(axis=-1)
            x, y, z = v[..., 0] / m, v[..., 1] / m, -v[..., 2] / m
            vf = 0.5 - 0.5 * y
            left = ((x + y >= 0) & (y + z >= 0) & (-z - x <= 0)) | ((x + y <= 0) & (-y + z >= 0) & (z - x >= 0))
            uf = np.where(left, 0.25 * x + 0.25, 0.75 - 0.25 * x)
            xy = np.stack([uf * self.width, vf * self.height], axis=-1)
            ok = np.isfinite(m) & (m > 0)
            ok &= self.snap_to_image(xy)
        return clean(xy, ok, inplace=True)


#: lenslab's frame -> the frame v360's tetrahedron formulas are written in (axis signs: +y down)
FRAME_SIGN = np.array([1.0, -1.0, 1.0])
#: the tetrahedron's corner directions in that frame
CORNERS = np.array([[1.0, 1.0, -1.0], [-1.0, -1.0, -1.0], [1.0, -1.0, 1.0], [-1.0, 1.0, 1.0]])
