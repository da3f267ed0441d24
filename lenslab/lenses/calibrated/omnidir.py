"""Mei's unified omnidirectional model, as ``cv2.omnidir`` (Kalibr's omni-radtan)."""

from __future__ import annotations

import numpy as np

from lenslab.lenses.core.base import Param, ReferencePoint
from lenslab.lenses.calibrated.intrinsics import SIZE_PARAMS, Calibrated, coefficient_params, intrinsics_params
from lenslab.lenses.formulas.kinds import UNIFIED
from lenslab.lenses.calibrated.polydistort import PolyDistortion
from lenslab.lenses.registry import register


@register
class Omnidir(Calibrated):
    r"""Mei's unified model: the unit sphere seen from ``xi`` behind its centre, then radtan distortion.

    In OpenCV's frame, for a unit ray ``(X, Y, Z)``: ``x = X / (Z + xi)``, ``y = Y / (Z + xi)``; then
    ``x_d = x (1 + k1 r^2 + k2 r^4) + 2 p1 x y + p2 (r^2 + 2 x^2)`` (``y`` likewise) and
    ``u = fx x_d + s y_d + cx``, ``v = fy y_d + cy``: ``cv2.omnidir.projectPoints`` with
    ``K = [[fx, s, cx], [0, fy, cy], [0, 0, 1]]``, ``D = (k1, k2, p1, p2)``.

    Validity: ``Z > -min(xi, 1/xi)``. Below ``xi = 1`` that keeps ``Z + xi > 0``; above it the map
    folds where ``1 + xi Z = 0``, so ``xi > 1`` sees beyond 180 degrees, up to ``acos(-1/xi)`` from the
    axis, and the undistorted radius stays below ``1 / sqrt(xi^2 - 1)``. The lifting back to the sphere is
    closed form (``(xi + sqrt(1 + (1 - xi^2) r^2)) / (r^2 + 1)``); undistortion is the shared Newton solve.
    Reference: C. Mei and P. Rives, "Single view point omnidirectional camera calibration from planar
    grids", ICRA 2007.
    """

    name = "omnidir"
    #: specs and image sizes the conformance tests run on (round trips, extremes)
    examples = (
        ('omnidir:fx=1000,fy=1000,cx=511.5,cy=511.5,xi=1.6,k1=-0.05,k2=0.01,p1=0.001,p2=-0.002,width=1024,'
         'height=1024', (8192, 8192)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways)
    reference_points = (
        ReferencePoint('omnidir:fx=400,fy=400,cx=511.5,cy=511.5,xi=1.6,k1=-0.05,k2=0.01,p1=0.001,p2=-0.002,'
                       'width=1024,height=1024', (1024, 1024), (692.2531983161336, 615.2401240828586),
                       (0.8427009716003844, -0.48154341234307685, 0.24077170617153842),
                       'cv2.omnidir.projectPoints (OpenCV 5.0.0)'),
    )
    #: (true spec, perturbed start, fitted parameters) a fit recovers exactly, on a 256 x 192 image
    fit_examples = (
        ('omnidir:fx=120,fy=120,cx=127.5,cy=95.5,xi=0.8,k1=-0.02,width=256,height=192',
         'omnidir:fx=115,fy=115,cx=127.5,cy=95.5,xi=0.7,k1=0,width=256,height=192', 'fx,fy,xi,k1'),
    )
    summary = "Mei's unified omnidirectional model (cv2.omnidir, Kalibr omni): xi, k1, k2, p1, p2, skew s"
    params = (
        intrinsics_params(500.0, 500.0, 499.5, 499.5)
        + (Param("s", 0.0, "skew, px (K[0][1])"),
           Param("xi", 1.0, "distance of the projection centre behind the sphere's centre", 0.0, None))
        + coefficient_params("k1 k2 p1 p2", "radtan distortion coefficient (cv2.omnidir's D order)")
        + SIZE_PARAMS
    )
    skew_name = "s"

    @property
    def w(self) -> float:
        """``Z > -w`` is the region the model sees."""
        xi = self.xi
        return min(xi, 1.0 / xi) if xi > 0 else 0.0

    @property
    def radius_limit(self) -> float:
        return 1.0 / np.sqrt(self.xi * self.xi - 1.0) if self.xi > 1 else np.inf

    def make_distortion(self):
        return PolyDistortion(a=(self.k1, self.k2), p1=self.p1, p2=self.p2, limit=self.radius_limit)

    kernel_kind = UNIFIED  # (X, Y) / (Z + xi) for unit rays, valid for Z > -w

    def kernel_params(self):
        return (self.xi, self.w)
