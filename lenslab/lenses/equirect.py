"""Equirectangular (latitude/longitude) panoramas."""

from __future__ import annotations

import numpy as np

from lenslab.errors import LensError
from lenslab.lenses.base import FLOAT, Lens, Param, as_points, clean, normalize
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
    summary = "latitude/longitude panorama (full sphere, or a longitude/latitude range)"
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

    @property
    def full_sphere(self) -> bool:
        return (self.lon_min, self.lon_max, self.lat_min, self.lat_max) == (-180.0, 180.0, -90.0, 90.0)

    @property
    def wraps(self) -> bool:
        """True when the left and right edges are the same meridian."""
        return self.lon_max - self.lon_min == 360.0

    # normalised-plane maps, so that swirl and the distortions can bend an equirect too; a bent point
    # outside the longitude/latitude rectangle is invalid (the map would repeat directions there)
    def uv_to_dir(self, uv):
        return self.pixel_to_dir(self.uv_to_pixel(uv))

    def dir_to_uv(self, d):
        xy, valid = self.dir_to_pixel(d)
        return self.pixel_to_uv(xy), valid

    def pixel_to_dir(self, xy):
        with np.errstate(all="ignore"):  # non-finite or absurd pixels are flagged, not warned about
            return self._pixel_to_dir(as_points(xy, 2, "pixel coordinates"))

    def _pixel_to_dir(self, xy):
        lon0, lon1 = np.radians(self.lon_min), np.radians(self.lon_max)
        lat0, lat1 = np.radians(self.lat_min), np.radians(self.lat_max)
        if self.full_sphere:  # the exact forms of the conventions
            phi = (2.0 * xy[..., 0] / self.width - 1.0) * np.pi
            theta = (1.0 - 2.0 * xy[..., 1] / self.height) * (np.pi / 2)
        else:
            phi = lon0 + (xy[..., 0] / self.width) * (lon1 - lon0)
            theta = lat1 - (xy[..., 1] / self.height) * (lat1 - lat0)
        ct = np.cos(theta)
        d = np.stack([ct * np.sin(phi), np.sin(theta), ct * np.cos(phi)], axis=-1)
        # exact poles at the edges, whatever cos(pi/2) rounds to
        top = xy[..., 1] == 0
        bottom = xy[..., 1] == self.height
        if self.lat_max == 90.0 and np.any(top):
            d[top] = (0.0, 1.0, 0.0)
        if self.lat_min == -90.0 and np.any(bottom):
            d[bottom] = (0.0, -1.0, 0.0)
        return clean(d, self.in_image(xy))

    def dir_to_pixel(self, dirs):
        d = normalize(as_points(dirs, 3, "directions"))
        phi = np.arctan2(d[..., 0], d[..., 2])
        theta = np.arctan2(d[..., 1], np.hypot(d[..., 0], d[..., 2]))
        if self.full_sphere:
            x = (phi / np.pi + 1.0) * (0.5 * self.width)
            y = (1.0 - theta / (np.pi / 2)) * (0.5 * self.height)
            valid = np.ones(x.shape, dtype=bool)
        else:
            lon0, lon1 = np.radians(self.lon_min), np.radians(self.lon_max)
            lat0, lat1 = np.radians(self.lat_min), np.radians(self.lat_max)
            if not self.wraps:  # bring phi into [lon0, lon0 + 2pi)
                phi = lon0 + np.mod(phi - lon0, 2 * np.pi)
            x = (phi - lon0) / (lon1 - lon0) * self.width
            y = (lat1 - theta) / (lat1 - lat0) * self.height
            valid = None
        xy = np.stack([x, y], axis=-1).astype(FLOAT)
        if valid is None:
            valid = self.snap_to_image(xy)  # within edge_slack of the range counts, moved onto the edge
        valid &= np.any(d != 0, axis=-1)
        return clean(xy, valid, inplace=True)
