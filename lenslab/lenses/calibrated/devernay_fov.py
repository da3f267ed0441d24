"""The FOV model of Devernay and Faugeras (COLMAP's FOV camera, Project Tango's calibrations)."""

from __future__ import annotations

import math

from lenslab.lenses.core.base import Param, ReferencePoint
from lenslab.lenses.calibrated.intrinsics import SIZE_PARAMS, Calibrated, intrinsics_params
from lenslab.lenses.formulas.kinds import FOV
from lenslab.lenses.registry import register


@register
class DevernayFOV(Calibrated):
    r"""FOV model: a pinhole whose image radius follows ``r_d = atan(2 r_u tan(omega/2)) / omega``.

    In OpenCV's frame, ``r_u = |(X/Z, Y/Z)|``, the point is scaled to ``r_d`` and
    ``u = fx x + cx``, ``v = fy y + cy`` (OpenCV pixels; COLMAP's ``cx, cy`` are these plus 0.5). The
    inverse is closed form, ``r_u = tan(r_d omega) / (2 tan(omega/2))``, valid for ``r_d omega < pi/2``;
    ``omega = 0`` is the plain pinhole. Reference: F. Devernay, O. Faugeras, "Straight lines have to be
    straight", Machine Vision and Applications 13(1), 2001; COLMAP's ``FOVCameraModel``.
    """

    name = "devernay-fov"
    #: specs and image sizes the conformance tests run on (round trips, extremes)
    examples = (
        ('devernay-fov:fx=400,fy=400,cx=511.5,cy=383.5,omega=0.9,width=1024,height=768', (8192, 6144)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways)
    reference_points = (
        ReferencePoint('devernay-fov:fx=400,fy=400,cx=511.5,cy=383.5,omega=0.9,width=1024,height=768',
                       (1024, 768), (635.1770719384133, 281.35244005132233),
                       (0.2794478596995734, 0.23287321641631117, 0.9314928656652447),
                       'pycolmap 4.2.1 FOV camera img_from_cam'),
    )
    #: (true spec, perturbed start, fitted parameters) a fit recovers exactly, on a 256 x 192 image
    fit_examples = (
        ('devernay-fov:fx=150,fy=150,cx=127.5,cy=95.5,omega=0.8,width=256,height=192',
         'devernay-fov:fx=140,fy=140,cx=127.5,cy=95.5,omega=0.6,width=256,height=192', 'fx,fy,omega'),
    )
    summary = "FOV model of Devernay and Faugeras (COLMAP FOV): fx, fy, cx, cy, omega"
    params = (
        intrinsics_params(500.0, 500.0, 499.5, 499.5)
        + (Param("omega", 0.5, "field-of-view parameter, radians (0: no distortion)", 0.0, math.pi, hi_open=True),)
        + SIZE_PARAMS
    )
    kernel_kind = FOV

    def kernel_params(self):
        return (self.omega, 2.0 * math.tan(self.omega / 2.0))
