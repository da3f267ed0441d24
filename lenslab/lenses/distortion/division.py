"""Radial distortion with the division model: pincushion and barrel."""

from __future__ import annotations

import numpy as np

from lenslab.lenses.core.base import Param, ReferencePoint
from lenslab.lenses.registry import register
from lenslab.lenses.formulas.solve import DIVISION, DIVISION_RECIPROCAL, inverse_table, kernel_settings
from lenslab.lenses.core.wrapped import Wrapped


def smallest_positive_root(c2: float, c1: float, c0: float = 1.0) -> float:
    """Smallest positive root of ``c2 s^2 + c1 s + c0`` (``inf`` if there is none)."""
    if c2 == 0.0:
        if c1 == 0.0:
            return np.inf
        s = -c0 / c1
        return s if s > 0 else np.inf
    disc = c1 * c1 - 4.0 * c2 * c0
    if disc < 0:
        return np.inf
    q = -0.5 * (c1 + np.copysign(np.sqrt(disc), c1))  # the stable pair of roots q/c2, c0/q
    with np.errstate(over="ignore", divide="ignore"):  # a tiny c2 puts one root at infinity
        roots = [r for r in ((q / c2) if q != 0 else np.inf, (c0 / q) if q != 0 else np.inf) if r > 0]
    return float(min(roots)) if roots else np.inf


@register
class Distortion(Wrapped):
    r"""Radial distortion, division model: ``r_u = r_d / (1 + k1 r_d^2 + k2 r_d^4)``.

    ``r_d = sqrt(u^2 + v^2)`` is the radius in the image; the point is scaled to ``r_u`` (i.e.
    ``(u, v) / (1 + k1 r_d^2 + k2 r_d^4)``, no division by ``r_d``) and goes through the base model
    (perspective by default). ``k1 > 0`` gives pincushion, ``k1 < 0`` barrel.

    The lens folds over where ``r_u(r_d)`` stops increasing: with ``s = r_d^2``,
    ``dr_u/dr_d = (1 - k1 s - 3 k2 s^2) / (1 + k1 s + k2 s^2)^2``; the first positive root of the
    numerator or of the denominator bounds the valid disc. Pixels at or beyond it are invalid.

    The inverse (direction -> pixel) has no closed form: ``r_u = f(r_d)`` is solved for ``r_d`` by
    Newton's method inside the bracket ``[0, r_fold]`` with bisection whenever a step leaves it or
    fails to halve the previous one, starting from a table of the inverse (from the
    exact ``k2 = 0`` root ``2 r_u / (1 + sqrt(1 - 4 k1 r_u^2))``), until the step is below 1e-13 or
    the residual is at rounding level; directions whose solve does not converge are reported invalid. When the bound is a pole of ``r_u`` (the denominator's root), radii ``r_u > 1``
    are solved as ``-1/r_u = -(1 + k1 r_d^2 + k2 r_d^4) / r_d``, which stays straight next to the pole.
    """

    name = "distortion"
    #: specs and image sizes the conformance tests run on (round trips, extremes)
    examples = (
        ('distortion:k1=0.1,k2=0.02', (8192, 4608)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways)
    reference_points = (
        ReferencePoint('distortion:k1=0.1,k2=0.02', (640, 480), (420.5, 180.25),
                       (0.29146158568730685, 0.17328188800812525, 0.9407568928033322),
                       'division model r_u = r_d / (1 + k1 r_d^2 + k2 r_d^4) (docs/conventions.md), then a pinhole'),
    )
    #: (true spec, perturbed start, fitted parameters) a fit recovers exactly, on a 256 x 192 image
    fit_examples = (
        ('distortion:k1=-0.12,k2=0.02,fov=75', 'distortion:k1=-0.05,k2=0,fov=65', 'k1,k2,fov'),
    )
    summary = "radial distortion, division model (k1 > 0 pincushion, k1 < 0 barrel)"
    own_params = (
        Param("k1", 0.3, "r^2 coefficient of the division model (> 0 pincushion, < 0 barrel)"),
        Param("k2", 0.0, "r^4 coefficient of the division model"),
    )

    def _check(self) -> None:
        k1, k2 = self.k1, self.k2
        s_slope = smallest_positive_root(-3.0 * k2, -k1)  # dr_u/dr_d = 0: a true fold
        s_pole = smallest_positive_root(k2, k1)  # 1 + k1 s + k2 s^2 = 0: r_u runs off to infinity
        s_fold = min(s_slope, s_pole)
        self.pole = bool(np.isfinite(s_pole) and s_pole <= s_slope)
        self.r_fold = float(np.sqrt(s_fold))  # image radius of the fold (inf: none)
        # its square as the pixel test computes it, so that r >= r_fold <=> u^2 + v^2 >= s_fold exactly
        self.s_fold = self.r_fold * self.r_fold
        # the inverse never needs to look beyond the image corner
        self.r_corner = float(np.hypot(1.0, self.aspect)) * (1.0 + 1e-9)

    def radius_map(self, r_d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``r_u`` and ``dr_u/dr_d`` at image radii ``r_d`` (float64)."""
        s = r_d * r_d
        den = 1.0 + s * (self.k1 + self.k2 * s)
        num = 1.0 - s * (self.k1 + 3.0 * self.k2 * s)
        with np.errstate(divide="ignore", invalid="ignore"):
            r_u = r_d / den
            slope = num / (den * den)
        if self.pole:  # at and past the pole r_u is +inf (rounding must not flip its sign there)
            r_u = np.where(den > 0, r_u, np.inf)
        return r_u, slope

    def _reciprocal_radius_map(self, r_d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``-1/r_u`` and its derivative ``N / r_d^2``: the same root, straight next to a pole."""
        s = r_d * r_d
        den = 1.0 + s * (self.k1 + self.k2 * s)
        num = 1.0 - s * (self.k1 + 3.0 * self.k2 * s)
        with np.errstate(divide="ignore", invalid="ignore"):
            return -den / r_d, num / s

    def bend(self, uv):
        u, v = uv[..., 0], uv[..., 1]
        s = u * u + v * v
        den = s * self.k2
        den += self.k1
        den *= s
        den += 1.0
        out = uv / den[..., None]
        return out, s < self.s_fold

    def _kernel_args(self):
        """Bracket, range and starting-guess table of the compiled inverse (built once)."""
        if getattr(self, "_kargs", None) is None:
            hi = min(self.r_fold, self.r_corner)
            folds = hi == self.r_fold
            f_hi = np.inf if (folds and self.pole) else float(self.radius_map(np.array([hi]))[0][0])
            table, step = inverse_table(self.radius_map, hi, cap=1e3)
            self._kargs = (hi, f_hi, folds, self.pole and folds, table, step)
        return self._kargs

    def unbend(self, uv):
        """Image ``(u, v)`` of undistorted points: the compiled solve of ``r_u = f(r_d)``, fused with the
        range test and rescaling (a safeguarded Newton from a table of the inverse)."""
        from lenslab.lenses.core.native import lens_kernels, run_rows

        hi, f_hi, strict, pole, table, step = self._kernel_args()
        return run_rows(uv, 2, lambda flat, out, valid: lens_kernels().division_unbend(
            flat, self.k1, self.k2, hi, f_hi, strict, pole, table, step, *kernel_settings(), out, valid))


@register
class Pincushion(Distortion):
    r"""Pincushion distortion (division model with ``k1 > 0``): ``r_u = r_d / (1 + k1 r_d^2 + k2 r_d^4)``.

    The edges are magnified more than the centre. Same equations, fold and inverse as ``distortion``.
    """

    name = "pincushion"
    #: specs and image sizes the conformance tests run on (round trips, extremes)
    examples = (
        ('pincushion:k1=0.3,k2=0.05,fov=90', (8192, 4608)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways)
    reference_points = (
        ReferencePoint('pincushion:k1=0.3,k2=0.05,fov=90', (640, 480), (420.5, 180.25),
                       (0.2846824051537886, 0.1692514796809838, 0.9435623269406487),
                       'division model r_u = r_d / (1 + k1 r_d^2 + k2 r_d^4) (docs/conventions.md), then a pinhole'),
    )
    #: (true spec, perturbed start, fitted parameters) a fit recovers exactly, on a 256 x 192 image
    fit_examples = (
        ('pincushion:k1=0.2,k2=0.01,fov=60', 'pincushion:k1=0.1,k2=0,fov=70', 'k1,k2,fov'),
    )
    summary = "pincushion distortion: division model with k1 > 0"
    own_params = (
        Param("k1", 0.3, "r^2 coefficient (> 0 for pincushion)", 0.0, None, lo_open=True),
        Param("k2", 0.0, "r^4 coefficient"),
    )


@register
class Barrel(Distortion):
    r"""Barrel distortion (division model with ``k1 < 0``): ``r_u = r_d / (1 + k1 r_d^2 + k2 r_d^4)``.

    The edges are squeezed toward the centre. Same equations, fold and inverse as ``distortion``.
    """

    name = "barrel"
    #: specs and image sizes the conformance tests run on (round trips, extremes)
    examples = (
        ('barrel:k1=-0.3,fov=100', (8192, 4608)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways)
    reference_points = (
        ReferencePoint('barrel:k1=-0.3,fov=100', (640, 480), (420.5, 180.25),
                       (0.3550781789999239, 0.2111036934850294, 0.9106891442172114),
                       'division model r_u = r_d / (1 + k1 r_d^2 + k2 r_d^4) (docs/conventions.md), then a pinhole'),
    )
    #: (true spec, perturbed start, fitted parameters) a fit recovers exactly, on a 256 x 192 image
    fit_examples = (
        ('barrel:k1=-0.2,k2=0.01,fov=80', 'barrel:k1=-0.1,k2=0,fov=70', 'k1,k2,fov'),
    )
    summary = "barrel distortion: division model with k1 < 0"
    own_params = (
        Param("k1", -0.3, "r^2 coefficient (< 0 for barrel)", None, 0.0, hi_open=True),
        Param("k2", 0.0, "r^4 coefficient"),
    )
