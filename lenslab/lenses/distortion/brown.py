"""Radial distortion with the Brown (Brown-Conrady) polynomial."""

from __future__ import annotations

import numpy as np

from lenslab.lenses.core.base import FLOAT, Param, PixelKernel, ReferencePoint
from lenslab.lenses.distortion.division import smallest_positive_root
from lenslab.lenses.registry import register
from lenslab.lenses.formulas.solve import BROWN, inverse_table, kernel_settings
from lenslab.lenses.core.wrapped import Wrapped


@register
class Brown(Wrapped):
    r"""Radial distortion, Brown polynomial: ``r_d = r_u (1 + k1 r_u^2 + k2 r_u^4)``.

    ``r_u`` is the radius of the ideal (undistorted) point seen by the base model (perspective by
    default) and ``r_d = sqrt(u^2 + v^2)`` its radius in the image; ``k1 < 0`` barrel, ``k1 > 0``
    pincushion. The direction -> pixel side is the closed form; pixel -> direction solves the
    polynomial for ``r_u`` by bracketed Newton (start ``r_u = r_d``, bisection whenever a step leaves the
    bracket, stop below 1e-13, no fixed count). With ``s = r_u^2`` the polynomial folds where
    ``dr_d/dr_u = 1 + 3 k1 s + 5 k2 s^2`` reaches 0: pixels at or beyond the fold radius are invalid.
    """

    name = "brown"
    #: specs and image sizes the conformance tests run on (round trips, extremes)
    examples = (
        ('brown:k1=-0.05', (8192, 4608)),
        ('brown:k1=0.1,k2=0.05,base=fisheye,fov=150', (8192, 8192)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways)
    reference_points = (
        ReferencePoint('brown:k1=-0.05', (640, 480), (431.09000000000003, 303.48),
                       (0.3246172270321178, -0.18549555830406733, 0.9274777915203366),
                       'Brown polynomial r_d = r_u (1 + k1 r_u^2 + k2 r_u^4) (docs/conventions.md), of a '
                       'fov-90 pinhole'),
    )
    #: (true spec, perturbed start, fitted parameters) a fit recovers exactly, on a 256 x 192 image
    fit_examples = (
        ('brown:k1=0.05,k2=-0.01,fov=60', 'brown:k1=0,k2=0,fov=70', 'k1,k2,fov'),
    )
    summary = "radial distortion, Brown polynomial r_d = r_u (1 + k1 r_u^2 + k2 r_u^4)"
    own_params = (
        Param("k1", -0.05, "r^2 coefficient (< 0 barrel, > 0 pincushion)"),
        Param("k2", 0.0, "r^4 coefficient"),
    )

    def _check(self) -> None:
        s_fold = smallest_positive_root(5.0 * self.k2, 3.0 * self.k1)
        self.ru_fold = float(np.sqrt(s_fold))  # undistorted radius of the fold (inf: none)
        with np.errstate(over="ignore", invalid="ignore"):  # a fold at an astronomic radius (k1 ~ 1e-300)
            rd_fold = float(self.radius_map(np.array([self.ru_fold]))[0][0]) if np.isfinite(s_fold) else np.inf
        self.rd_fold = rd_fold if np.isfinite(rd_fold) else np.inf
        # bracket for the solve: the fold, or far enough that every image radius is inside
        r_corner = float(np.hypot(1.0, self.aspect))
        hi = self.ru_fold
        if not np.isfinite(hi):
            hi = r_corner
            while self.radius_map(np.array([hi]))[0][0] < r_corner:
                hi *= 2.0
        self.ru_hi = hi

    def radius_map(self, r_u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``r_d`` and ``dr_d/dr_u`` at undistorted radii ``r_u`` (float64)."""
        s = r_u * r_u
        return r_u * (1.0 + s * (self.k1 + self.k2 * s)), 1.0 + s * (3.0 * self.k1 + 5.0 * self.k2 * s)

    def bend(self, uv):
        """Undistorted ``(u, v) r_u / r_d`` (limit 1 at the centre): the compiled solve of
        ``r_d = g(r_u)`` fused with the range test (a safeguarded Newton from a table of the inverse)."""
        from lenslab.lenses.core.native import lens_kernels, run_rows

        if getattr(self, "_table", None) is None:
            self._table = inverse_table(self.radius_map, min(self.ru_fold, self.ru_hi))
        table, step = self._table
        return run_rows(uv, 2, lambda flat, out, valid: lens_kernels().brown_bend(
            flat, self.k1, self.k2, self.ru_hi, self.rd_fold, table, step, *kernel_settings(), out, valid))

    def pixel_kernel(self):
        """The compiled ``dir -> pixel`` of a Brown-distorted pinhole (``brown_pixels``: the NumPy steps of the
        perspective's :meth:`dir_to_uv`, :meth:`unbend` and :meth:`Lens.dir_to_pixel`, in their order); None for
        other bases."""
        from lenslab.lenses.core.native import kernel_holds, lens_kernels
        from lenslab.lenses.projections.perspective import Perspective

        base = self.base_lens
        if type(base) is not Perspective or not kernel_holds(self, Brown, ("unbend",)):
            return None
        return PixelKernel(lens_kernels().brown_pixels, np.array(
            [self.width, self.height, self.aspect, base.t, base.tv, self.k1, self.k2, self.ru_fold * self.ru_fold,
             self.edge_slack], dtype=FLOAT))

    def unbend(self, uv):
        u, v = uv[..., 0], uv[..., 1]
        s = u * u + v * v
        poly = 1.0 + s * (self.k1 + self.k2 * s)
        return uv * poly[..., None], s < self.ru_fold * self.ru_fold
