"""Cylindrical projections: the central cylinder, Lambert's equal-area cylinder and Mercator.

All three put longitude linearly across the width and differ only in how latitude is spaced::

    phi = u F                          (F = fov/2, the longitude at the left and right edges)
    cylindrical              v F = tan(theta)             (a cylinder seen from its axis: verticals straight)
    cylindrical-equal-area   v F = sin(theta)             (Lambert, 1772: equal areas on the sphere stay equal)
    mercator                 v F = atanh(sin(theta))      (Mercator, 1569: conformal, = ln tan(pi/4 + theta/2))

with ``theta`` the latitude and ``d = (cos theta sin phi, sin theta, cos theta cos phi)``. Pixels are
square (one radian of longitude at the equator is as long as one radian of latitude there), so the image's
aspect sets the latitude range; or ``vfov`` sets the latitude range across the height instead
(``h(theta) / h(vfov/2)`` runs from -1 at the bottom edge to 1 at the top, ``h`` the model's spacing),
as ffmpeg's v360 does. References: J. P. Snyder, *Map Projections - A Working Manual*, USGS
Professional Paper 1395 (1987), sections 7 (Mercator) and 10 (cylindrical equal-area).

>>> import numpy as np
>>> from lenslab.lenses import make_lens
>>> lens = make_lens("mercator", (512, 512))   # square: latitudes up to atan(sinh(pi)) = 85.05 degrees
>>> xy, ok = lens.dir_to_pixel([[0.0, np.sin(np.radians(45)), np.cos(np.radians(45))]])
>>> round(float(xy[0, 1]), 6)   # y = H/2 (1 - atanh(sin 45 deg) / pi)
184.179219
"""

from __future__ import annotations

import numpy as np

from lenslab.lenses.core.base import FLOAT, DirKernel, Lens, Param, PixelKernel, ReferencePoint, Seams
from lenslab.lenses.formulas import lonlat
from lenslab.lenses.registry import register

#: slack on the longitude test of the inverse: a direction on the left or right edge comes back a few
#: ulps outside the range and must still count as seen
LON_SLACK = 1e-12


class _Cylinder(Lens):
    """Longitude linear in u; latitude through :meth:`lat_to_v` / :meth:`v_to_lat` (per model)."""

    params = (
        Param("fov", 360.0, "longitude range across the image width, degrees", 0.0, 360.0, lo_open=True),
        Param("vfov", 0.0, "latitude range across the image height, degrees (0: square pixels)", 0.0, 180.0),
    )
    #: how ffmpeg's v360 reads this projection as its input (lenslab.warp.compat_v360)
    v360_read = "span"
    #: whether the model reaches the poles at a finite height (vfov = 180 allowed)
    vfov_180 = False

    def _check(self) -> None:
        from lenslab.errors import LensError

        if self.vfov >= 180.0 and not self.vfov_180:
            raise LensError(f"{self.name}: vfov must be below 180 (the poles are at infinity)")
        self.F = float(np.radians(self.fov) / 2.0)
        if self.vfov > 0:
            half = np.radians(self.vfov) / 2.0
            top, _ = self.lat_to_v(np.array(np.sin(half)), np.array(np.cos(half)))
            self.Fv = float(top) / self.aspect  # v Fv = h(theta): v = aspect at the top edge
        else:
            self.Fv = self.F

    quiet_defaults = {"vfov": 0.0}  # 0: square pixels from fov

    #: the frame the model fills at fov 360 with square pixels, width / height (lenslab warp's default size)
    frame_aspect = 2.0

    @property
    def wraps(self) -> bool:
        """True when the left and right edges are the same meridian (fov = 360)."""
        return self.fov == 360.0

    def seams(self) -> Seams:
        """A full turn wraps (period W); with it, Lambert's cylinder at vfov 180 has its poles on the edges."""
        if not self.wraps:
            return Seams()
        poles = self.vfov == 180.0
        return Seams(float(self.width), poles, poles)

    def column_scale(self, y):
        """Length on the sphere of one column step over one row step at rows ``y``:
        ``cos(theta) h'(theta) F / Fv`` for latitude spacing ``v Fv = h(theta)``."""
        v = (1.0 - 2.0 * np.asarray(y, dtype=FLOAT) / self.height) * self.aspect
        s, c, _ = self.v_to_lat(v * self.Fv)
        return c * self.slope(s, c) * (self.F / self.Fv)

    def slope(self, s, c):
        """``h'(theta)`` at latitude with sine ``s`` and cosine ``c``."""
        raise NotImplementedError

    #: the latitude spacing (:mod:`lenslab.lenses.formulas.lonlat`'s code)
    kind: int = -1

    def uv_to_dir(self, uv):
        phi = uv[..., 0] * self.F
        sin_t, cos_t, ok = self.v_to_lat(uv[..., 1] * self.Fv)
        return lonlat.lonlat_to_dir(phi, sin_t, cos_t), ok & (np.abs(phi) <= np.pi)

    def dir_kernel(self):
        """The compiled ``pixel -> dir`` (``cylinder_dirs``: the NumPy steps of :meth:`uv_to_dir` through
        :meth:`Lens.pixel_to_dir`, in their order)."""
        from lenslab.lenses.core.native import dir_kernel_holds, lens_kernels

        if not dir_kernel_holds(self, _Cylinder, ("v_to_lat",)):
            return None
        return DirKernel(lens_kernels().cylinder_dirs, np.array(
            [self.width, self.height, self.aspect, self.kind, self.F, self.Fv, 1.0 + LON_SLACK], dtype=FLOAT))

    def pixel_kernel(self):
        """The compiled ``dir -> pixel`` (``cylinder_pixels``: the NumPy steps of :meth:`dir_to_uv` through
        :meth:`Lens.dir_to_pixel`, in their order)."""
        from lenslab.lenses.core.native import kernel_holds, lens_kernels

        if not kernel_holds(self, _Cylinder, ("lat_to_v",)):
            return None
        return PixelKernel(lens_kernels().cylinder_pixels, np.array(
            [self.width, self.height, self.aspect, self.kind, self.F, self.Fv, self.F * (1.0 + LON_SLACK),
             self.edge_slack], dtype=FLOAT))

    def dir_to_uv(self, d):
        phi, s, c = lonlat.dir_to_lonlat(d)
        uv = np.empty(d.shape[:-1] + (2,), dtype=FLOAT)
        np.divide(phi, self.F, out=uv[..., 0])
        v, ok = self.lat_to_v(s, c)
        np.divide(v, self.Fv, out=uv[..., 1])
        ok &= np.abs(phi) <= self.F * (1.0 + LON_SLACK)
        return uv, ok

    def v_to_lat(self, y):
        """(sin, cos) of the latitude at ``y = v F`` and whether it exists."""
        return lonlat.height_to_lat(self.kind, y, LON_SLACK)

    def lat_to_v(self, s, c):
        """``v F`` for latitude with sine ``s`` and cosine ``c >= 0``, and whether it is finite."""
        return lonlat.lat_to_height(self.kind, s, c)


@register
class Cylindrical(_Cylinder):
    r"""Central cylindrical projection: ``phi = u F``, ``tan(theta) = v F`` (F = fov/2).

    Rays through the axis of a cylinder wrapped round the camera: vertical lines stay straight and
    horizontal lines bend. The poles are at infinity (never in the image). v360's ``cylindrical``.
    """

    name = "cylindrical"
    #: specs and image sizes the conformance tests run on (round trips, extremes)
    examples = (
        ('cylindrical', (8192, 4096)),
        ('cylindrical:fov=180,vfov=120', (8192, 4096)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways)
    reference_points = (
        ReferencePoint('cylindrical', (1024, 512), (700.5, 153.85),
                       (0.7756761933274652, 0.5310858436764139, 0.34099013145767837),
                       'J. P. Snyder, Map Projections - A Working Manual (1987), float64'),
    )
    #: (true spec, perturbed start, fitted parameters) a fit recovers exactly, on a 256 x 192 image
    fit_examples = (
        ('cylindrical:fov=200', 'cylindrical:fov=180', 'fov'),
    )
    summary = "central cylinder: longitude across, tan(latitude) up (straight verticals)"

    kind = lonlat.CYLINDRICAL
    #: as v360's input, a direction this projection does not see reads the top-left pixel (lenslab.lenses.core.v360)
    v360_unseen = "top-left"

    def slope(self, s, c):  # d tan / d theta = 1 / cos^2
        return 1.0 / (c * c)


@register
class CylindricalEqualArea(_Cylinder):
    r"""Lambert cylindrical equal-area projection: ``phi = u F``, ``sin(theta) = v F`` (F = fov/2).

    Equal areas of the image hold equal solid angles; the poles are the lines ``v F = +-1``, beyond
    which there are no rays. v360's ``cylindricalea``.
    """

    name = "cylindrical-equal-area"
    #: specs and image sizes the conformance tests run on (round trips, extremes)
    examples = (
        ('cylindrical-equal-area', (8192, 2608)),
        ('cylindrical-equal-area:vfov=180', (8192, 4096)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways)
    reference_points = (
        ReferencePoint('cylindrical-equal-area', (1024, 300), (700.5, 90.25),
                       (0.8517062217670701, 0.3666214083046682, 0.37441321394411864),
                       'J. P. Snyder, Map Projections - A Working Manual (1987), float64'),
    )
    #: (true spec, perturbed start, fitted parameters) a fit recovers exactly, on a 256 x 192 image
    fit_examples = (
        ('cylindrical-equal-area:fov=300', 'cylindrical-equal-area:fov=280', 'fov'),
    )
    summary = "Lambert's equal-area cylinder: longitude across, sin(latitude) up"
    frame_aspect = np.pi  # the poles on the top and bottom edges
    vfov_180 = True

    kind = lonlat.EQUAL_AREA_CYLINDRICAL

    def slope(self, s, c):  # d sin / d theta = cos
        return c


@register
class Mercator(_Cylinder):
    r"""Mercator projection: ``phi = u F``, ``v F = atanh(sin theta) = ln tan(pi/4 + theta/2)`` (F = fov/2).

    Conformal (small shapes keep their form); the poles are at infinity. On a square image with
    fov = 360 the latitudes reach +-85.05 degrees (``atan(sinh(pi))``), the square of web maps and of
    ffmpeg's v360 ``mercator``. The inverse of the latitude is ``sin theta = tanh(v F)``,
    ``cos theta = 1 / cosh(v F)``.
    """

    name = "mercator"
    #: specs and image sizes the conformance tests run on (round trips, extremes)
    examples = (
        ('mercator', (8192, 8192)),
        ('mercator:fov=200,vfov=150', (8192, 4096)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways)
    reference_points = (
        ReferencePoint('mercator', (512, 512), (350.25, 153.85),
                       (0.4833023300590044, 0.8492814434215842, 0.21246149679244883),
                       'J. P. Snyder, Map Projections - A Working Manual (1987), float64'),
    )
    #: (true spec, perturbed start, fitted parameters) a fit recovers exactly, on a 256 x 192 image
    fit_examples = (
        ('mercator:fov=250', 'mercator:fov=230', 'fov'),
    )
    summary = "Mercator: conformal, longitude across, atanh(sin latitude) up"
    frame_aspect = 1.0  # latitudes to 85.05 degrees, the square of web maps

    kind = lonlat.MERCATOR

    def v360_dir_to_pixel(self, d):
        """Where v360 reads this Mercator frame as its input: past its top and bottom rows, clamped to them."""
        phi, s, c = lonlat.dir_to_lonlat(d)
        with np.errstate(all="ignore"):
            v, _ = self.lat_to_v(s, c)
            uv = np.stack([phi / self.F, v / self.Fv], axis=-1)
            px = self.uv_to_pixel(uv)
            np.clip(px[..., 1], 0.0, self.height, out=px[..., 1])
            ok = np.abs(phi) <= self.F * (1.0 + LON_SLACK)
        return px, ok & np.isfinite(px).all(axis=-1)

    def slope(self, s, c):  # d atanh(sin) / d theta = 1 / cos
        return 1.0 / c
