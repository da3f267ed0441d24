"""The enhanced unified camera model of Khomutenko, Garcia and Martinet (RA-L 2016), as in Basalt."""

from __future__ import annotations

from lenslab.lenses.core.base import Param, ReferencePoint
from lenslab.lenses.calibrated.intrinsics import SIZE_PARAMS, Calibrated, intrinsics_params
from lenslab.lenses.formulas.kinds import EUCM as EUCM_KIND
from lenslab.lenses.calibrated.double_sphere import alpha_w
from lenslab.lenses.registry import register


@register
class EUCM(Calibrated):
    r"""Enhanced unified camera model: the unit sphere stretched into an ellipsoid by ``beta``.

    In OpenCV's frame::

        d = sqrt(beta (x^2 + y^2) + z^2)
        u = fx x / (alpha d + (1 - alpha) z) + cx,   v likewise with fy, y, cy

    valid for ``z > -w d`` with ``w = alpha/(1 - alpha)`` for ``alpha <= 0.5`` else ``(1 - alpha)/alpha``.
    The inverse is closed form: with ``m = ((u - cx)/fx, (v - cy)/fy)``, ``r^2 = |m|^2``,
    ``mz = (1 - beta alpha^2 r^2) / (alpha sqrt(1 - (2 alpha - 1) beta r^2) + 1 - alpha)``, valid for
    ``r^2 <= 1/(beta (2 alpha - 1))`` when ``alpha > 0.5``; the ray is ``(mx, my, mz)`` normalised.
    Reference: B. Khomutenko, G. Garcia, P. Martinet, "An Enhanced Unified Camera Model", IEEE RA-L 1(1),
    2016; the validity region as given by Usenko et al., 3DV 2018.
    """

    name = "eucm"
    #: specs and image sizes the conformance tests run on (round trips, extremes)
    examples = (
        ('eucm:fx=200,fy=200,cx=511.5,cy=511.5,alpha=0.6,beta=1.1,width=1024,height=1024', (8192, 8192)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways)
    reference_points = (
        ReferencePoint('eucm:fx=200,fy=200,cx=511.5,cy=511.5,alpha=0.6,beta=1.1,width=1024,height=1024',
                       (1024, 1024), (796.5055574357381, 440.8736106410655),
                       (0.9630868246861536, 0.2407717061715384, 0.1203858530857692),
                       'Khomutenko, Garcia and Martinet, An Enhanced Unified Camera Model (RA-L 2016), eq. 4'),
    )
    #: (true spec, perturbed start, fitted parameters) a fit recovers exactly, on a 256 x 192 image
    fit_examples = (
        ('eucm:fx=60,fy=60,cx=127.5,cy=95.5,alpha=0.6,beta=1.1,width=256,height=192',
         'eucm:fx=55,fy=55,cx=127.5,cy=95.5,alpha=0.55,beta=1.0,width=256,height=192', 'fx,fy,alpha,beta'),
    )
    summary = "enhanced unified camera model (Khomutenko et al. 2016; Basalt, Kalibr eucm): alpha, beta"
    params = (
        intrinsics_params(250.0, 250.0, 499.5, 499.5)
        + (Param("alpha", 0.5, "projection parameter", 0.0, 1.0),
           Param("beta", 1.0, "ellipsoid parameter", 0.0, None, lo_open=True))
        + SIZE_PARAMS
    )

    def _check(self) -> None:
        super()._check()
        self.w = alpha_w(self.alpha)

    kernel_kind = EUCM_KIND  # the projection above, compiled

    def kernel_params(self):
        return (self.alpha, self.beta, self.w)
