"""The tan-fold fisheye: the angle grows as tan(r F), steeply towards the rim, and folds back past fov 144.7.

Model name ``tan-fisheye``; ``seedfisheye`` is its former name and still reads (an alias)."""

from __future__ import annotations

import numpy as np

from lenslab.lenses.core.base import FLOAT, Lens, Param, ReferencePoint
from lenslab.lenses.registry import register
from lenslab.lenses.formulas.solve import inverse_table, kernel_settings

#: tan(F r) may rise to pi: there the direction reaches the back pole, and beyond it the image folds
T_FOLD = np.pi


@register
class TanFisheye(Lens):
    r"""Tan-fold fisheye: ``t = tan(r F)``, ``d ~ (sin(t) u, sin(t) v, cos(t))``, normalised.

    With ``r = sqrt(u^2 + v^2)`` and ``F = fov/2``. Because ``(u, v)`` is not divided by ``r``, the
    angle from the axis is ``psi(r) = atan2(r sin t, cos t)`` (about ``F r^2`` near the centre), not
    ``t``; at the rim (``r = 1``) it is ``t = tan(F)``. Consequences, for the record:

    - the rim passes 90 degrees from the axis once fov exceeds 2 atan(pi/2) = 115.0 degrees;
    - where ``t`` reaches pi the direction is the back pole ``-z`` for every azimuth, and beyond it the
      image folds back over directions already seen (not injective): this happens inside the image
      once ``tan(F) > pi``, fov above 2 atan(pi) = 144.7 degrees, at ``r = atan(pi) / F``;
    - ``tan`` diverges at the rim when fov = 180.

    Valid pixels: ``r <= 1`` and ``t < pi``; on that disc ``psi`` is increasing, since
    ``dpsi/dr ~ sin(t) cos(t) + r F (1 + t^2) > 0`` for ``t`` in ``[0, pi)``. The inverse solves
    ``psi(r) = theta`` (angle of the direction from the axis) by bracketed Newton from
    ``r0 = sqrt(theta / F)``; directions it cannot reach or whose solve does not converge are invalid.
    """

    name = "tan-fisheye"
    #: specs and image sizes the conformance tests run on (round trips, extremes)
    examples = (
        ('tan-fisheye:fov=120', (8192, 8192)),
        ('seedfisheye:fov=170', (8192, 8192)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways)
    reference_points = (
        ReferencePoint('tan-fisheye:fov=120', (512, 512), (300.5, 200.25),
                       (0.05364183431096745, 0.06720297219857159, 0.9962962983668227),
                       'the tan-fold formula rad = r F, t = tan(rad), d ~ (sin(t) u, sin(t) v, cos(t)), float64'),
    )
    #: (true spec, perturbed start, fitted parameters) a fit recovers exactly, on a 256 x 192 image
    fit_examples = (
        ('tan-fisheye:fov=100', 'tan-fisheye:fov=80', 'fov'),
    )
    aliases = ("seedfisheye",)
    summary = "tan-fold fisheye: angle from tan(r F), steep towards the rim (folds back above fov 144.7)"
    params = (
        Param("fov", 180.0, "the formula's fov parameter F = fov/2, degrees (not the angle actually seen)",
              0.0, 180.0, lo_open=True),
    )

    def _check(self) -> None:
        self.F = float(np.radians(self.fov) / 2.0)
        # radius of the fold (t = pi), or the rim when the fold lies outside the image circle
        self.r_max = min(1.0, float(np.arctan(T_FOLD) / self.F))
        self.folds = self.r_max < 1.0

    def psi(self, r: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Angle from the axis and its derivative at image radius ``r`` (float64)."""
        t = np.tan(r * self.F)
        st, ct = np.sin(t), np.cos(t)
        y = r * st
        den = ct * ct + y * y
        dt = self.F * (1.0 + t * t)
        psi = np.arctan2(y, ct)
        psi[y < 0] += 2.0 * np.pi  # past the fold (t > pi): keep psi increasing so the bracket holds
        return psi, (st * ct + r * dt) / den

    @property
    def max_angle(self) -> float:
        """Largest angle from the axis the lens sees (radians); pi (not reached) when it folds."""
        return float(np.pi if self.folds else self.psi(np.array([1.0]))[0][0])

    def uv_to_dir(self, uv):
        u, v = uv[..., 0], uv[..., 1]
        r = np.sqrt(u * u + v * v)
        t = np.tan(r * self.F)
        st = np.sin(t)
        d = np.empty(uv.shape[:-1] + (3,), dtype=FLOAT)
        np.multiply(u, st, out=d[..., 0])
        np.multiply(v, st, out=d[..., 1])
        np.cos(t, out=d[..., 2])
        d /= np.sqrt(np.einsum("...i,...i->...", d, d))[..., None]
        valid = r <= 1.0 + 1e-12  # the rim, to rounding (the inverse returns r <= 1 up to an ulp)
        if self.folds:
            valid &= r < self.r_max
        valid &= (t >= 0) & (t < T_FOLD)
        return d, valid

    def dir_to_uv(self, d):
        """Solve ``psi(r) = theta`` per direction: compiled bracketed Newton from a table guess."""
        from lenslab.lenses.core.native import lens_kernels, run_rows

        if getattr(self, "_table", None) is None:
            self._table = inverse_table(self.psi, self.r_max, sqrt_map=True)
        table, step = self._table
        psi_max = self.max_angle if self.folds else self.max_angle * (1.0 + 1e-12)
        return run_rows(d, 2, lambda flat, out, valid: lens_kernels().tan_fisheye_dir_to_uv(
            flat, self.F, self.r_max, psi_max, self.folds, table, step, *kernel_settings(), out, valid))


#: the class's former name
SeedFisheye = TanFisheye
