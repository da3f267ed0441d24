"""Equirectangular (latitude/longitude) panoramas."""

from __future__ import annotations

import numpy as np

from lenslab.errors import LensError
from lenslab.lenses.core.base import (FLOAT, DirKernel, Lens, Param, PixelKernel, ReferencePoint, Seams, as_points,
                                     clean)
from lenslab.lenses.formulas import lonlat
from lenslab.lenses.registry import register


@register
class Equirect(Lens):
    r"""Equirectangular projection, the full sphere by default.

    Longitude and latitude are linear in the pixel coordinates::

        phi   = lon_min + (x / W) * (lon_max - lon_min)      # 0 = forward (+z), positive toward +x
        theta = lat_max - (y / H) * (lat_max - lat_min)      # +90 at the top = +y
        d     = (cos(theta) sin(phi), sin(theta), cos(theta) cos(phi))

    With the default range (-180..180, -90..90) this is ``phi = (2x/W - 1) pi``,
    ``theta = (1 - 2y/H) pi/2``: the left and right edges are the same meridian (the seam) and the top
    and bottom edges are the poles. The inverse is ``phi = atan2(dx, dz)``,
    ``theta = atan2(dy, hypot(dx, dz))``.
    """

    name = "equirect"
    #: specs and image sizes the conformance tests run on (round trips, extremes)
    examples = (
        ('equirect', (8192, 4096)),
        ('equirect:lon_min=-90,lon_max=120,lat_min=-30,lat_max=60', (8192, 3000)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways)
    reference_points = (
        ReferencePoint('equirect', (800, 400), (620.25, 130.5),
                       (0.8438986849711829, 0.5191462344390729, -0.13535950935061536),
                       'latitude/longitude definition (v360 equirect), float64'),
    )
    #: (true spec, perturbed start, fitted parameters) a fit recovers exactly, on a 256 x 192 image
    fit_examples = (
        ('equirect:lon_min=-60,lon_max=60,lat_min=-30,lat_max=40',
         'equirect:lon_min=-50,lon_max=70,lat_min=-35,lat_max=30', 'lon_min,lon_max,lat_min,lat_max'),
    )
    summary = "latitude/longitude panorama (full sphere, or a longitude/latitude range)"
    #: how ffmpeg's v360 reads this projection as its input (lenslab.warp.compat_v360)
    v360_read = "span"
    params = (
        Param("lon_min", -180.0, "left edge longitude, degrees", -180.0, 180.0),
        Param("lon_max", 180.0, "right edge longitude, degrees", -180.0, 180.0),
        Param("lat_min", -90.0, "bottom edge latitude, degrees", -90.0, 90.0),
        Param("lat_max", 90.0, "top edge latitude, degrees", -90.0, 90.0),
    )

    def _check(self) -> None:
        if not self.lon_min < self.lon_max:
            raise LensError(f"equirect: lon_min ({self.lon_min}) must be below lon_max ({self.lon_max})")
        if not self.lat_min < self.lat_max:
            raise LensError(f"equirect: lat_min ({self.lat_min}) must be below lat_max ({self.lat_max})")

    @staticmethod
    def probe_size(values: dict) -> tuple[int, int]:
        """A size to make it at before its :meth:`default_frame` is asked (any size holds its ranges)."""
        return 360, 180

    def default_frame(self, rows: int) -> tuple[int, int]:
        """The size made without ``--size`` from ``rows`` rows over 180 degrees: square pixels over its ranges
        (1024 x 512 for the whole sphere from 512 rows, 1024 x 256 for latitudes -45 to 45)."""
        return (max(1, round(rows * (self.lon_max - self.lon_min) / 180.0)),
                max(1, round(rows * (self.lat_max - self.lat_min) / 180.0)))

    def pixels_per_degree(self) -> float:
        """Its rows over the latitudes they span (180 degrees for the full sphere; 90 for a band of -45 to 45)."""
        return self.height / (self.lat_max - self.lat_min)

    @property
    def full_sphere(self) -> bool:
        return (self.lon_min, self.lon_max, self.lat_min, self.lat_max) == (-180.0, 180.0, -90.0, 90.0)

    @property
    def wraps(self) -> bool:
        """True when the left and right edges are the same meridian."""
        return self.lon_max - self.lon_min == 360.0

    def seams(self) -> Seams:
        """A full turn wraps (period W); with it, a latitude range reaching +-90 has poles."""
        if not self.wraps:
            return Seams()
        return Seams(float(self.width), self.lat_max == 90.0, self.lat_min == -90.0)

    def pixel_kernel(self) -> PixelKernel:
        """The compiled inverse: ``equirect_pixels`` of ``lenslab.cxx_kernels`` (C++, no JIT) with
        (W, H, lon/lat range in radians, flags, edge slack)."""
        from lenslab.lenses.core.native import lens_kernels

        params = np.array([self.width, self.height, np.radians(self.lon_min), np.radians(self.lon_max),
                           np.radians(self.lat_min), np.radians(self.lat_max), float(self.full_sphere),
                           float(self.wraps), self.edge_slack], dtype=FLOAT)
        return PixelKernel(lens_kernels().equirect_pixels, params)

    def column_scale(self, y):
        """cos(latitude) x (radians per column) / (radians per row): columns crowd toward the poles."""
        lat = np.radians(self.lat_max - (np.asarray(y, dtype=FLOAT) / self.height) * (self.lat_max - self.lat_min))
        return np.abs(np.cos(lat)) * (np.radians(self.lon_max - self.lon_min) / self.width) / (
            np.radians(self.lat_max - self.lat_min) / self.height)

    # normalised-plane maps, so that swirl and the distortions can bend an equirect too; a bent point
    # outside the longitude/latitude rectangle is invalid (the map would repeat directions there)
    def uv_to_dir(self, uv):
        return self.pixel_to_dir(self.uv_to_pixel(uv))

    def dir_to_uv(self, d):
        xy, valid = self.dir_to_pixel(d)
        return self.pixel_to_uv(xy), valid

    def pixel_to_dir(self, xy):
        """Unit directions of pixels: the compiled :meth:`dir_kernel` when it still describes this lens, else the
        NumPy steps of :meth:`_pixel_to_dir` (non-finite or absurd pixels are flagged, not warned about)."""
        from lenslab.lenses.core.native import pixel_to_dir_through

        return pixel_to_dir_through(self, xy, self._pixel_to_dir)

    def dir_kernel(self):
        """The compiled ``pixel -> dir`` (``equirect_dirs``: the steps of :meth:`_pixel_to_dir` in their order, the
        sines and cosines from glibc's vector maths, within a few ulps of NumPy's own; the NumPy steps stay its
        reference) with (W, H, whole sphere, lon/lat range in radians, pole at the top, pole at the bottom)."""
        from lenslab.lenses.core.native import dir_kernel_holds, lens_kernels

        if not dir_kernel_holds(self, Equirect, ("_pixel_to_dir", "in_image", "full_sphere")):
            return None
        return DirKernel(lens_kernels().equirect_dirs, np.array(
            [self.width, self.height, float(self.full_sphere), np.radians(self.lon_min), np.radians(self.lon_max),
             np.radians(self.lat_min), np.radians(self.lat_max), float(self.lat_max == 90.0),
             float(self.lat_min == -90.0)], dtype=FLOAT))

    def _pixel_to_dir(self, xy):
        lon0, lon1 = np.radians(self.lon_min), np.radians(self.lon_max)
        lat0, lat1 = np.radians(self.lat_min), np.radians(self.lat_max)
        x, y = xy[..., 0], xy[..., 1]
        if self.full_sphere:  # the exact forms of the conventions, in this order
            phi = 2.0 * x
            phi /= self.width
            phi -= 1.0
            phi *= np.pi
            theta = 2.0 * y
            theta /= self.height
            np.subtract(1.0, theta, out=theta)
            theta *= np.pi / 2
        else:
            phi = x / self.width
            phi *= lon1 - lon0
            phi += lon0
            theta = y / self.height
            theta *= lat1 - lat0
            np.subtract(lat1, theta, out=theta)
        d = lonlat.lonlat_to_dir(phi, np.sin(theta), np.cos(theta))
        # exact poles at the edges, whatever cos(pi/2) rounds to
        if self.lat_max == 90.0:
            top = y == 0
            if top.any():
                d[top] = (0.0, 1.0, 0.0)
        if self.lat_min == -90.0:
            bottom = y == self.height
            if bottom.any():
                d[bottom] = (0.0, -1.0, 0.0)
        return clean(d, self.in_image(xy), inplace=True)

    def dir_to_pixel(self, dirs):
        d = as_points(dirs, 3, "directions")
        with np.errstate(all="ignore"):
            return self._dir_to_pixel(d)

    def _dir_to_pixel(self, d):
        # atan2 needs no unit vectors: only zero and non-finite directions are flagged
        n2 = np.einsum("...i,...i->...", d, d)
        ok = (n2 > 0) & np.isfinite(n2)
        phi, sin_t, cos_t = lonlat.dir_to_lonlat(d)
        theta, _ = lonlat.lat_to_height(lonlat.EQUIRECTANGULAR, sin_t, cos_t)
        xy = np.empty(d.shape[:-1] + (2,), dtype=FLOAT)
        x, y = xy[..., 0], xy[..., 1]
        if self.full_sphere:
            np.divide(phi, np.pi, out=x)  # x = (phi/pi + 1) W/2, y = (1 - theta/(pi/2)) H/2
            x += 1.0
            x *= 0.5 * self.width
            np.divide(theta, np.pi / 2, out=y)
            np.subtract(1.0, y, out=y)
            y *= 0.5 * self.height
            valid = ok
        else:
            lon0, lon1 = np.radians(self.lon_min), np.radians(self.lon_max)
            lat0, lat1 = np.radians(self.lat_min), np.radians(self.lat_max)
            if not self.wraps:  # bring phi into [lon0, lon0 + 2pi) (atan2 gives [-pi, pi], lon0 >= -pi)
                phi[phi < lon0] += 2 * np.pi
            np.subtract(phi, lon0, out=x)
            x /= lon1 - lon0
            x *= self.width
            np.subtract(lat1, theta, out=y)
            y /= lat1 - lat0
            y *= self.height
            valid = ok & self.snap_to_image(xy)  # within edge_slack of the range counts, moved onto the edge
        np.copyto(xy, 0.0, where=~valid[..., None])  # atan2 of finite values: finite everywhere else
        return xy, valid
