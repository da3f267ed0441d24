"""The Pannini (Panini) projection: wide views with straight verticals and radial lines.

T. K. Sharpless, B. Postle and D. M. German, "Pannini: A New Projection for Rendering Wide Angle
Perspective Images", Computational Aesthetics in Graphics, Visualization and Imaging (2010). A point
at longitude ``phi`` and latitude ``theta`` is seen from a distance ``d`` behind the centre of a unit
cylinder and projected onto a plane::

    S = (d + 1) / (d + cos phi)
    x = S sin phi,    y = S tan theta                     (Sharpless et al., eq. 1-2)

``d = 0`` is the rectilinear (perspective) view, ``d = 1`` the stereographic cylinder (Pannini's
classic), large ``d`` tends to the cylindrical equidistant view. Lenslab scales the image so that the
left and right edges sit at ``phi = +-fov/2``: ``u = x / x_F``, ``v = y' / x_F`` with
``x_F = S(F) sin F``. ``vcomp`` compresses verticals: ``y' = tan(theta) (1 + (1 - vcomp)(S - 1))`` (0: the
paper's y, 1: the central scale kept at every longitude, undoing the vertical stretch toward the sides;
verticals stay straight for every value).

The inverse of x has a closed form (the paper's, also ffmpeg's ``pannini``): with ``k = x^2/(d+1)^2``,
``cos phi = (-k d + sqrt(k^2 d^2 - (k+1)(k d^2 - 1))) / (k+1)`` and ``phi = atan2(x, S cos phi)``.
Longitudes reach ``acos(-d)`` for ``d <= 1`` (where S diverges) and ``acos(-1/d)`` for ``d > 1`` (where
x turns back), so ``fov/2`` must stay below that.

>>> from lenslab.lenses import make_lens
>>> lens = make_lens("pannini:d=1,fov=106.26020470831197", (400, 400))   # x_F = 1: ffmpeg's scale
>>> round(lens.x_f, 12)
1.0
"""

from __future__ import annotations

import numpy as np

from lenslab.errors import LensError
from lenslab.lenses.core.base import FLOAT, DirKernel, Lens, Param, PixelKernel, ReferencePoint
from lenslab.lenses.registry import register


def pannini_x(phi, d: float):
    """Sharpless's ``x = S sin phi`` with ``S = (d + 1) / (d + cos phi)`` (float64).

    ``d + cos phi`` is taken as ``(d - 1) + 2 cos^2(phi / 2)``: the same value without the cancellation
    that rounds it to 0 near ``phi = pi`` for ``d = 1``, where x tends to ``2 tan(phi / 2)``.
    """
    return (d + 1.0) * np.sin(phi) / ((d - 1.0) + 2.0 * np.cos(phi / 2.0) ** 2)


def max_longitude(d: float) -> float:
    """Largest longitude (radians) the projection reaches: acos(-d) for d <= 1, acos(-1/d) above."""
    return float(np.arccos(-d if d <= 1.0 else -1.0 / d))


@register
class Pannini(Lens):
    r"""Pannini projection (Sharpless, Postle and German 2010): straight verticals, wide views.

    ``x = S sin phi``, ``y = S tan theta``, ``S = (d + 1) / (d + cos phi)``, scaled so that the image width
    spans ``fov``; ``vcomp`` in [0, 1] compresses verticals toward the sides. See the module docstring for the inverse.
    """

    name = "pannini"
    #: specs and image sizes the conformance tests run on (round trips, extremes)
    examples = (
        ('pannini', (8192, 4608)),
        ('pannini:d=2,fov=239.9,vcomp=0.5', (8192, 4608)),
        ('pannini:d=0.5,fov=230', (8192, 4096)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways)
    reference_points = (
        ReferencePoint('pannini:fov=150,d=1', (800, 600), (533.1072281941099, 243.71978799409655),
                       (0.4698689469495153, 0.19866933079506122, 0.8600893382050473),
                       'Sharpless, Postle and German 2010, eqs. of the Pannini projection, float64'),
    )
    #: (true spec, perturbed start, fitted parameters) a fit recovers exactly, on a 256 x 192 image
    fit_examples = (
        ('pannini:fov=140,d=0.8,vcomp=0.3', 'pannini:fov=130,d=0.6,vcomp=0.2', 'fov,d,vcomp'),
    )
    summary = "Pannini: wide views with straight verticals (distance d, vertical compression)"
    #: how ffmpeg's v360 reads this projection as its input (lenslab.warp.compat_v360)
    v360_read = "span"
    #: as v360's input, a direction this projection does not see reads the top-left pixel (lenslab.lenses.core.v360)
    v360_unseen = "top-left"
    #: the frame the model fills, width / height (the default output size of lenslab warp)
    frame_aspect = 1.5
    params = (
        Param("fov", 150.0, "horizontal field of view, degrees (below 2 acos(-d), or 2 acos(-1/d) for d > 1)",
              0.0, 360.0, lo_open=True, hi_open=True),
        Param("d", 1.0, "distance of the centre of projection behind the cylinder's axis (0: perspective, "
              "1: classic Pannini)", 0.0, 1e6),
        Param("vcomp", 0.0, "vertical compression, 0 (none) to 1 (full)", 0.0, 1.0),
    )

    def _check(self) -> None:
        F = np.radians(self.fov) / 2.0
        limit = max_longitude(self.d)
        if not F < limit:
            raise LensError(f"pannini: fov={self.fov:g} is too wide for d={self.d:g} (it needs fov < "
                            f"{2 * np.degrees(limit):.6g}); use a narrower fov or a smaller d")
        self.F = float(F)
        self.x_f = float(pannini_x(F, self.d))
        # |phi| <= F  <=>  cos(phi) >= cos(F) (F <= pi), with the slack of a direction on the edge
        self._cos_edge = float(np.cos(F * (1.0 + 1e-12)))

    def _vscale(self, S):
        return 1.0 + (1.0 - self.vcomp) * (S - 1.0)

    def dir_kernel(self):
        """The compiled ``pixel -> dir`` (``pannini_dirs``: the NumPy steps of :meth:`uv_to_dir` through
        :meth:`Lens.pixel_to_dir`, in their order)."""
        from lenslab.lenses.core.native import dir_kernel_holds, lens_kernels

        if not dir_kernel_holds(self, Pannini, ("_vscale",)):
            return None
        d = self.d
        return DirKernel(lens_kernels().pannini_dirs, np.array(
            [self.width, self.height, self.aspect, d, self.x_f, (d + 1.0) ** 2, 1.0 - d * d,
             self.F * (1.0 + 1e-12) + 1e-15, 1.0 - self.vcomp], dtype=FLOAT))

    def uv_to_dir(self, uv):
        d = self.d
        x = uv[..., 0] * self.x_f
        y = uv[..., 1] * self.x_f
        k = x * x / ((d + 1.0) ** 2)
        disc = 1.0 + k * (1.0 - d * d)  # k^2 d^2 - (k + 1)(k d^2 - 1)
        ok = disc >= 0
        root = np.sqrt(np.maximum(disc, 0.0))
        clon = (root - k * d) / (k + 1.0)
        S = (d + 1.0) * (k + 1.0) / (d + root)  # d + cos phi = (d + root) / (k + 1), never 0
        phi = np.arctan2(x, S * clon)
        ok &= np.abs(phi) <= self.F * (1.0 + 1e-12) + 1e-15
        tan_t = y / self._vscale(S)
        c = 1.0 / np.sqrt(1.0 + tan_t * tan_t)  # cos(latitude)
        out = np.empty(uv.shape[:-1] + (3,), dtype=FLOAT)
        np.multiply(np.sin(phi), c, out=out[..., 0])
        np.multiply(tan_t, c, out=out[..., 1])
        np.multiply(np.cos(phi), c, out=out[..., 2])
        return out, ok & np.isfinite(tan_t)

    def pixel_kernel(self):
        """The compiled ``dir -> pixel`` (``pannini_pixels``: the NumPy steps of :meth:`dir_to_uv` through
        :meth:`Lens.dir_to_pixel`, in their order)."""
        from lenslab.lenses.core.native import kernel_holds, lens_kernels

        if not kernel_holds(self, Pannini, ("_vscale",)):
            return None
        return PixelKernel(lens_kernels().pannini_pixels, np.array(
            [self.width, self.height, self.aspect, self.d, self.x_f, self._cos_edge, 1.0 - self.vcomp,
             self.edge_slack], dtype=FLOAT))

    def dir_to_uv(self, dv):
        dx, dy, dz = dv[..., 0], dv[..., 1], dv[..., 2]
        c = np.hypot(dx, dz)  # cos(latitude); cos(phi) = dz / c, sin(phi) = dx / c
        inv_c = np.divide(1.0, c, out=np.zeros_like(c), where=c > 0)
        d = self.d
        cphi = dz * inv_c
        S = d + cphi
        ok = (cphi >= self._cos_edge) & (c > 0) & (S > 0)
        np.divide(d + 1.0, S, out=S, where=ok)  # S = (d + 1) / (d + cos phi)
        uv = np.empty(dv.shape[:-1] + (2,), dtype=FLOAT)
        np.multiply(dx, inv_c, out=uv[..., 0])
        uv[..., 0] *= S
        uv[..., 0] /= self.x_f
        np.multiply(dy, inv_c, out=uv[..., 1])  # tan(latitude)
        uv[..., 1] *= self._vscale(S)
        uv[..., 1] /= self.x_f
        return uv, ok & np.isfinite(uv).all(axis=-1)
