"""Fitzgibbon's one-parameter division model with pinhole intrinsics (COLMAP's DIVISION, SIMPLE_DIVISION)."""

from __future__ import annotations

import numpy as np

from lenslab.lenses.core.base import FLOAT, Param, as_points, clean
from lenslab.lenses.calibrated import SIZE_PARAMS, Calibrated, intrinsics_params
from lenslab.lenses.registry import register


@register
class Division(Calibrated):
    r"""Division model: a pixel's ray is ``(mx, my, 1 + k (mx^2 + my^2))`` with ``m = ((u - cx)/fx, (v - cy)/fy)``.

    In OpenCV's frame and pixels (lenslab's pixel minus 0.5). Both directions are closed form: a ray
    ``(X, Y, Z)`` with ``rho = |(X, Y)|`` lands at ``m = 2 (X, Y) / (Z + sqrt(Z^2 - 4 k rho^2))``.
    ``k > 0`` (barrel) folds over at ``|m| = 1/sqrt(k)``: pixels beyond it are invalid. ``k < 0``
    (pincushion) never folds: the ray passes 90 degrees where ``|m| = 1/sqrt(-k)`` and goes on behind
    the camera. Reference: A. Fitzgibbon, "Simultaneous linear estimation of multiple view geometry
    and lens distortion", CVPR 2001; COLMAP's ``DivisionCameraModel`` (``src/colmap/sensor/models.h``).
    """

    name = "division"
    summary = "Fitzgibbon division model with pinhole intrinsics (COLMAP DIVISION): fx, fy, cx, cy, k"
    params = (
        intrinsics_params(500.0, 500.0, 499.5, 499.5)
        + (Param("k", 0.0, "division coefficient: ray z = 1 + k |m|^2 on the normalised plane "
                 "(> 0 barrel, < 0 pincushion)"),)
        + SIZE_PARAMS
    )

    def pixel_to_dir(self, xy):
        xy = as_points(xy, 2, "pixel coordinates")
        with np.errstate(all="ignore"):
            mx, my = self.pixel_to_plane(xy[..., 0] - 0.5, xy[..., 1] - 0.5)
            r2 = mx * mx + my * my
            z = 1.0 + self.k * r2
            valid = np.isfinite(r2)
            if self.k > 0:  # beyond the fold the rays repeat
                valid &= r2 * self.k <= 1.0
            d = np.stack([mx, -my, z], axis=-1)
            d /= np.sqrt(r2 + z * z)[..., None]
        return clean(d, valid, inplace=True)

    def dir_to_pixel(self, dirs):
        d = as_points(dirs, 3, "directions")
        with np.errstate(all="ignore"):
            X, Y, Z = d[..., 0], -d[..., 1], d[..., 2]
            rho2 = X * X + Y * Y
            s = np.sqrt(Z * Z - 4.0 * self.k * rho2)
            # 2 / (Z + s), or (Z - s) / (2 k rho^2) where Z < 0 (no cancellation: same value)
            scale = np.where(Z >= 0, 2.0 / (Z + s), (Z - s) / (2.0 * self.k * rho2))
            valid = np.isfinite(s) & (Z + s > 0) & (rho2 + Z * Z > 0)
            mx, my = X * scale, Y * scale
            xy = np.stack([self.fx * mx + self.cx + 0.5, self.fy * my + self.cy + 0.5], axis=-1)
        valid &= np.isfinite(xy).all(axis=-1)
        xy = np.where(valid[..., None], xy, 0.0).astype(FLOAT)
        valid &= self.snap_to_image(xy)
        np.copyto(xy, 0.0, where=~valid[..., None])
        return xy, valid
