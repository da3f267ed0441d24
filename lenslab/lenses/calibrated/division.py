"""Fitzgibbon's one-parameter division model with pinhole intrinsics (COLMAP's DIVISION, SIMPLE_DIVISION)."""

from __future__ import annotations

import numpy as np

from lenslab.lenses.core.base import FLOAT, Param, ReferencePoint, as_points, clean
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
    #: specs and image sizes the conformance tests run on (round trips, extremes): barrel and pincushion
    examples = (
        ("division:fx=700,fy=690,cx=511.5,cy=511.5,k=0.25,width=1024,height=1024", (8192, 8192)),
        ("division:fx=700,fy=700,cx=511.5,cy=511.5,k=-0.2,width=1024,height=1024", (8192, 8192)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways): pycolmap 4.2.1's
    #: ``Camera.img_from_cam`` for COLMAP's DIVISION with the same numbers (COLMAP's cx, cy = these + 0.5)
    reference_points = (
        ReferencePoint("division:fx=700,fy=690,cx=511.5,cy=511.5,k=0.25,width=1024,height=1024", (1024, 1024),
                       (729.308305925152, 369.1973989634715),
                       (0.2822162605150792, 0.18814417367671948, 0.9407208683835974),
                       "pycolmap 4.2.1 Camera.img_from_cam, DIVISION [700, 690, 512, 512, 0.25], ray (0.3, -0.2, 1)"),
        ReferencePoint("division:fx=700,fy=700,cx=511.5,cy=511.5,k=-0.2,width=1024,height=1024", (1024, 1024),
                       (343.0360364364293, 748.5495489889989),
                       (-0.22965760608731267, -0.3215206485222377, 0.9186304243492507),
                       "pycolmap 4.2.1 Camera.img_from_cam, DIVISION [700, 700, 512, 512, -0.2], ray (-0.25, 0.35, 1)"),
    )
    #: (true spec, perturbed start, fitted parameters) a fit recovers exactly, on a 256 x 192 image
    fit_examples = (
        ("division:fx=150,fy=151,cx=127.5,cy=95.5,k=0.12,width=256,height=192",
         "division:fx=140,fy=140,cx=127.5,cy=95.5,k=0.05,width=256,height=192", "fx,fy,k"),
    )
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
