"""The Kannala-Brandt fisheye model (OpenCV's ``cv2.fisheye``, Kalibr's pinhole-equidistant)."""

from __future__ import annotations

import numpy as np

from lenslab.lenses.calibrated.intrinsics import SIZE_PARAMS, Calibrated, coefficient_params, intrinsics_params
from lenslab.lenses.formulas.kinds import EQUIDISTANT
from lenslab.lenses.calibrated.polydistort import PolyDistortion
from lenslab.lenses.core.base import ReferencePoint
from lenslab.lenses.registry import register


def equidistant_unproject(mx, my):
    """Inverse of :func:`equidistant_project`: ``theta = |m|``, valid for ``theta < pi``."""
    theta = np.hypot(mx, my)
    k = np.where(theta > 0, np.sin(theta) / np.where(theta > 0, theta, 1.0), 1.0)
    return mx * k, my * k, np.cos(theta), theta < np.pi


@register
class KannalaBrandt(Calibrated):
    r"""Kannala-Brandt fisheye: ``theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8)``.

    ``theta`` is the angle from the optical axis; in OpenCV's frame the point lands at
    ``(x, y) = theta_d (X, Y) / |(X, Y)|`` and ``u = fx x + cx``, ``v = fy y + cy`` (OpenCV pixels).
    Below 90 degrees this is ``cv2.fisheye.projectPoints``; unlike OpenCV (which divides by ``Z``) it
    goes on past 90 degrees, up to the end of the polynomial's monotone range (the first root of
    ``1 + 3 k1 theta^2 + 5 k2 theta^4 + 7 k3 theta^6 + 9 k4 theta^8``) or 180 degrees; beyond it
    directions are invalid. ``p1, p2, s1..s4`` add OpenCV's tangential and thin-prism terms on the
    same plane (COLMAP's THIN_PRISM_FISHEYE); they are 0 for the plain model. Pixel -> direction solves
    ``theta_d(theta)`` by bracketed Newton (2-D Newton with the extra terms). Reference: Kannala and
    Brandt, "A generic camera model and calibration method for conventional, wide-angle, and fish-eye
    lenses", IEEE TPAMI 28(8), 2006.
    """

    name = "kannala-brandt"
    #: specs and image sizes the conformance tests run on (round trips, extremes)
    examples = (
        ('kannala-brandt:fx=350,fy=350,cx=511.5,cy=511.5,k1=0.05,k2=-0.01,k3=0.003,k4=-0.0005,width=1024,'
         'height=1024', (8192, 8192)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways)
    reference_points = (
        ReferencePoint('kannala-brandt:fx=350,fy=350,cx=511.5,cy=511.5,k1=0.05,k2=-0.01,k3=0.003,k4=-0.0005,'
                       'width=1024,height=1024', (1024, 1024), (814.1266612775889, 360.93666936120553),
                       (0.7171371656006362, 0.3585685828003181, 0.5976143046671969),
                       'cv2.fisheye.projectPoints (OpenCV 5.0.0)'),
    )
    #: (true spec, perturbed start, fitted parameters) a fit recovers exactly, on a 256 x 192 image
    fit_examples = (
        ('kannala-brandt:fx=80,fy=80,cx=127.5,cy=95.5,k1=0.03,k2=-0.005,width=256,height=192',
         'kannala-brandt:fx=70,fy=70,cx=127.5,cy=95.5,k1=0,k2=0,width=256,height=192', 'fx,fy,k1,k2'),
    )
    summary = "Kannala-Brandt fisheye (cv2.fisheye, Kalibr equidistant): fx, fy, cx, cy, k1..k4"
    params = (
        intrinsics_params(318.3098861837907, 318.3098861837907, 499.5, 499.5)
        + coefficient_params("k1 k2 k3 k4", "Kannala-Brandt coefficient of theta^3, ^5, ^7, ^9")
        + coefficient_params("p1 p2 s1 s2 s3 s4", "tangential / thin prism coefficient on the fisheye plane "
                             "(COLMAP THIN_PRISM_FISHEYE; 0 for plain Kannala-Brandt)")
        + SIZE_PARAMS
    )

    def make_distortion(self):
        return PolyDistortion(a=(self.k1, self.k2, self.k3, self.k4), p1=self.p1, p2=self.p2,
                              s=(self.s1, self.s2, self.s3, self.s4), limit=np.pi)

    @property
    def max_angle(self) -> float:
        """Largest angle from the axis the model sees, radians (the end of its monotone range)."""
        return self.distortion.fold

    #: the equidistant plane theta (X, Y) / |(X, Y)|, theta = atan2(|(X, Y)|, Z); all but the back pole
    kernel_kind = EQUIDISTANT


@register
class OpenCVFisheye(KannalaBrandt):
    """``opencv-fisheye``: another name for ``kannala-brandt`` (OpenCV's ``cv2.fisheye`` model)."""

    name = "opencv-fisheye"
    #: specs and image sizes the conformance tests run on (round trips, extremes)
    examples = (
        ('opencv-fisheye:fx=300,fy=300,cx=511.5,cy=383.5,k1=0.02,width=1024,height=768', (8192, 6144)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways)
    reference_points = (
        ReferencePoint('opencv-fisheye:fx=300,fy=300,cx=511.5,cy=511.5,k1=0.02,width=1024,height=1024',
                       (1024, 1024), (765.9391612912143, 385.03041935439285),
                       (0.7171371656006362, 0.3585685828003181, 0.5976143046671969),
                       'cv2.fisheye.projectPoints (OpenCV 5.0.0)'),
    )
    #: (true spec, perturbed start, fitted parameters) a fit recovers exactly, on a 256 x 192 image
    fit_examples = (
        ('opencv-fisheye:fx=80,fy=80,cx=127.5,cy=95.5,k1=0.03,width=256,height=192',
         'opencv-fisheye:fx=75,fy=75,cx=127.5,cy=95.5,k1=0,width=256,height=192', 'fx,fy,k1'),
    )
    summary = "alias of kannala-brandt (OpenCV's cv2.fisheye model)"
