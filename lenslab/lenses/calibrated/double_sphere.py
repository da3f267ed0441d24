"""The double sphere model of Usenko, Demmel and Cremers (3DV 2018), as in Basalt and Kalibr (ds)."""

from __future__ import annotations

import numpy as np

from lenslab.lenses.core.base import Param, ReferencePoint
from lenslab.lenses.calibrated.intrinsics import SIZE_PARAMS, Calibrated, intrinsics_params
from lenslab.lenses.formulas.kinds import DOUBLE_SPHERE
from lenslab.lenses.registry import register


def alpha_w(alpha: float) -> float:
    """``w1`` of the papers: ``alpha / (1 - alpha)`` up to 0.5, ``(1 - alpha) / alpha`` above."""
    return alpha / (1.0 - alpha) if alpha <= 0.5 else (1.0 - alpha) / alpha


@register
class DoubleSphere(Calibrated):
    r"""Double sphere: a point projected on two unit spheres ``xi`` apart, then a pinhole shifted by ``alpha/(1 - alpha)``.

    In OpenCV's frame::

        d1 = |(x, y, z)|,   d2 = |(x, y, xi d1 + z)|
        u = fx x / (alpha d2 + (1 - alpha)(xi d1 + z)) + cx,   v likewise with fy, y, cy

    valid for ``z > -w2 d1`` with ``w2 = (w1 + xi) / sqrt(2 w1 xi + xi^2 + 1)``, ``w1 = alpha/(1 - alpha)``
    for ``alpha <= 0.5`` else ``(1 - alpha)/alpha``. The inverse is closed form: with
    ``m = ((u - cx)/fx, (v - cy)/fy)``, ``r^2 = |m|^2``,
    ``mz = (1 - alpha^2 r^2) / (alpha sqrt(1 - (2 alpha - 1) r^2) + 1 - alpha)``, valid for
    ``r^2 <= 1/(2 alpha - 1)`` when ``alpha > 0.5``, and the ray is
    ``(mz xi + sqrt(mz^2 + (1 - xi^2) r^2)) / (mz^2 + r^2) (mx, my, mz) - (0, 0, xi)``.
    Reference: V. Usenko, N. Demmel, D. Cremers, "The Double Sphere Camera Model", 3DV 2018, eqs. 40-47.
    """

    name = "double-sphere"
    #: specs and image sizes the conformance tests run on (round trips, extremes)
    examples = (
        ('double-sphere:fx=200,fy=200,cx=511.5,cy=511.5,xi=-0.2,alpha=0.6,width=1024,height=1024', (8192, 8192)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways)
    reference_points = (
        ReferencePoint('double-sphere:fx=200,fy=200,cx=511.5,cy=511.5,xi=-0.2,alpha=0.6,width=1024,height=1024',
                       (1024, 1024), (852.4920147767718, 426.87699630580704),
                       (0.9630868246861536, 0.2407717061715384, 0.1203858530857692),
                       'Usenko, Demmel and Cremers, The Double Sphere Camera Model (3DV 2018), eq. 40-41'),
    )
    #: (true spec, perturbed start, fitted parameters) a fit recovers exactly, on a 256 x 192 image
    fit_examples = (
        ('double-sphere:fx=60,fy=60,cx=127.5,cy=95.5,xi=-0.2,alpha=0.6,width=256,height=192',
         'double-sphere:fx=55,fy=55,cx=127.5,cy=95.5,xi=-0.1,alpha=0.55,width=256,height=192', 'fx,fy,xi,alpha'),
    )
    summary = "double sphere model (Usenko et al. 2018; Basalt, Kalibr ds): fx, fy, cx, cy, xi, alpha"
    params = (
        intrinsics_params(250.0, 250.0, 499.5, 499.5)
        + (Param("xi", 0.0, "distance between the two spheres' centres", -1.0, 1.0),
           Param("alpha", 0.5, "pinhole shift alpha / (1 - alpha)", 0.0, 1.0))
        + SIZE_PARAMS
    )

    def _check(self) -> None:
        super()._check()
        w1 = alpha_w(self.alpha)
        self.w2 = (w1 + self.xi) / np.sqrt(2.0 * w1 * self.xi + self.xi ** 2 + 1.0)

    kernel_kind = DOUBLE_SPHERE  # the projection above, compiled

    def kernel_params(self):
        return (self.xi, self.alpha, self.w2)
