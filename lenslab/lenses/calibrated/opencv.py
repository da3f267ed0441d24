"""OpenCV's pinhole camera with its whole distortion model, as ``cv2.projectPoints``."""

from __future__ import annotations

from lenslab.lenses.calibrated.intrinsics import SIZE_PARAMS, Calibrated, coefficient_params, intrinsics_params
from lenslab.lenses.formulas.kinds import RECTILINEAR as PINHOLE
from lenslab.lenses.calibrated.polydistort import PolyDistortion
from lenslab.lenses.core.base import ReferencePoint
from lenslab.lenses.registry import register


@register
class OpenCV(Calibrated):
    r"""OpenCV's camera model (``cv2.projectPoints``): pinhole, rational radial, tangential, thin prism.

    In OpenCV's frame (``X`` right, ``Y`` down, ``Z`` forward), ``x = X/Z``, ``y = Y/Z``,
    ``r^2 = x^2 + y^2``::

        x'' = x (1 + k1 r^2 + k2 r^4 + k3 r^6) / (1 + k4 r^2 + k5 r^4 + k6 r^6)
              + 2 p1 x y + p2 (r^2 + 2 x^2) + s1 r^2 + s2 r^4
        y'' = y (...) / (...) + p1 (r^2 + 2 y^2) + 2 p2 x y + s3 r^2 + s4 r^4
        u = fx x'' + cx,   v = fy y'' + cy          (OpenCV pixels: lenslab's x - 0.5, y - 0.5)

    Valid in front of the camera and inside the fold radius of the radial map (and where the
    map's Jacobian is positive). Pixel -> direction is solved: a bracketed Newton on the radius, then,
    with tangential or prism terms, a 2-D Newton (at most 40 iterations, residual below 1e-14 of the
    focal length); unconverged pixels are invalid. Reference: OpenCV, ``calib3d`` "Camera Calibration
    and 3D Reconstruction" (the tilt terms ``tauX, tauY`` are not modelled).
    """

    name = "opencv"
    #: specs and image sizes the conformance tests run on (round trips, extremes)
    examples = (
        ('opencv:fx=600,fy=600,cx=511.5,cy=383.5,k1=-0.28,k2=0.09,p1=0.001,p2=-0.0015,k3=-0.01,k4=0.02,'
         'k5=0.001,k6=0.0005,s1=0.001,s2=-0.0002,s3=0.0007,s4=0.0001,width=1024,height=768', (8192, 6144)),
        ('opencv:fx=500,fy=500,cx=511.5,cy=383.5,width=1024,height=768', (8192, 6144)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways)
    reference_points = (
        ReferencePoint('opencv:fx=600,fy=600,cx=511.5,cy=383.5,k1=-0.28,k2=0.09,p1=0.001,p2=-0.0015,k3=-0.01,'
                       'k4=0.02,k5=0.001,k6=0.0005,s1=0.001,s2=-0.0002,s3=0.0007,s4=0.0001,width=1024,'
                       'height=768', (1024, 768), (657.7682372609759, 489.0717457077667),
                       (0.23892015112877915, -0.17202250881272096, 0.9556806045151166),
                       'cv2.projectPoints (OpenCV 5.0.0)'),
    )
    #: (true spec, perturbed start, fitted parameters) a fit recovers exactly, on a 256 x 192 image
    fit_examples = (
        ('opencv:fx=200,fy=201,cx=127.5,cy=95.5,k1=-0.05,k2=0.005,width=256,height=192',
         'opencv:fx=190,fy=190,cx=127.5,cy=95.5,k1=-0.02,k2=0,width=256,height=192', 'fx,fy,k1,k2'),
    )
    summary = "OpenCV camera (cv2.projectPoints): fx, fy, cx, cy, k1..k6, p1, p2, s1..s4"
    params = (
        intrinsics_params(500.0, 500.0, 499.5, 499.5)
        + coefficient_params("k1 k2 p1 p2 k3 k4 k5 k6", "OpenCV distortion coefficient (distCoeffs order)")
        + coefficient_params("s1 s2 s3 s4", "thin prism coefficient")
        + SIZE_PARAMS
    )

    def make_distortion(self):
        return PolyDistortion(a=(self.k1, self.k2, self.k3), b=(self.k4, self.k5, self.k6), p1=self.p1, p2=self.p2,
                              s=(self.s1, self.s2, self.s3, self.s4))

    kernel_kind = PINHOLE  # (X/Z, Y/Z), valid for Z > 0
