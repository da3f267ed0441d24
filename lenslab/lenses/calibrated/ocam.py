"""Scaramuzza's omnidirectional model, as OCamCalib's ``calib_results.txt`` holds it."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.polynomial import polynomial as P

from lenslab.errors import LensError
from lenslab.lenses.core.base import FLOAT, Param, ReferencePoint, as_points, clean
from lenslab.lenses.calibrated.intrinsics import SIZE_PARAMS, Calibrated, unit_rows
from lenslab.lenses.calibrated.polydistort import first_positive_root
from lenslab.lenses.registry import register
from lenslab.lenses.formulas.solve import inverse_table, kernel_settings


def parse_coefficients(model: str, name: str, text: str) -> np.ndarray:
    """Numbers separated by spaces or semicolons, e.g. ``"-250 0 0.002"``."""
    parts = [p for p in str(text).replace(";", " ").split() if p]
    try:
        out = np.array([float(p) for p in parts], dtype=FLOAT)
    except ValueError:
        raise LensError(f"{model}: {name}={text!r} must be numbers separated by spaces or ';'") from None
    if not np.isfinite(out).all():
        raise LensError(f"{model}: {name} must be finite numbers")
    return out


def format_coefficients(c) -> str:
    return " ".join(repr(float(v)) for v in c)


@register
class OCam(Calibrated):
    r"""Scaramuzza's model (OCamCalib): a polynomial of the image radius gives the ray's third component.

    OCamCalib's frame: ``x`` along image rows (down), ``y`` along columns (right), ``z = x cross y``
    (away from the scene: the camera looks down ``-z``); pixel centres at integer ``(row, column)``
    counted from 0 (the C convention of ``calib_results.txt``): lenslab's ``(x, y)`` is OCamCalib's
    ``(row, column) = (y - 0.5, x - 0.5)``. With ``[row - xc, col - yc] = [[c, d], [e, 1]] [xp, yp]``
    and ``rho = |(xp, yp)|``, the ray is ``(xp, yp, pol(rho))``, ``pol(rho) = a0 + a1 rho + a2 rho^2 + ...``
    (``cam2world``). Directions -> pixels solves ``atan2(rho, -pol(rho)) = angle from the axis`` for
    ``rho`` exactly, by a compiled bracketed Newton from a table of the inverse; OCamCalib's
    ``world2cam`` evaluates ``invpol``, a fit of that inverse, kept here only to be written back. Valid up to the first radius where that
    angle stops increasing (the first positive root of ``rho pol'(rho) - pol(rho)``).
    Reference: D. Scaramuzza, A. Martinelli, R. Siegwart, "A Toolbox for Easily Calibrating
    Omnidirectional Cameras", IROS 2006; OCamCalib's ``ocam_functions.c``.
    """

    name = "ocam"
    #: specs and image sizes the conformance tests run on (round trips, extremes)
    examples = (
        ('ocam:pol=-250 0 0.002,xc=511.5,yc=511.5,width=1024,height=1024', (8192, 8192)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways)
    reference_points = (
        ReferencePoint('ocam:pol=-250 0 0.002,xc=511.5,yc=511.5,width=1024,height=1024', (1024, 1024), (700.5, 300.5),
                       (0.6344623771489801, 0.7118768847056196, 0.3011458002434823),
                       "Scaramuzza's OCamCalib cam2world (ocam_functions.c), c=1 d=e=0"),
    )
    #: (true spec, perturbed start, fitted parameters) a fit recovers exactly, on a 256 x 192 image
    fit_examples = (
        ('ocam:pol=-80 0 0.004,xc=96.2,yc=127.1,width=256,height=192',
         'ocam:pol=-80 0 0.004,xc=94,yc=130,width=256,height=192', 'xc,yc'),
    )
    summary = "Scaramuzza's omnidirectional model (OCamCalib calib_results.txt): pol, invpol, xc, yc, c, d, e"
    params = (
        Param("pol", "-250 0 0.002", "cam2world polynomial a0 a1 a2 ... (spaces or ';' between)"),
        Param("invpol", "", "world2cam polynomial as OCamCalib fitted it (kept for files; not used)"),
        Param("xc", 499.5, "centre row, px, counted from 0 (OCamCalib's C convention)"),
        Param("yc", 499.5, "centre column, px, counted from 0"),
        Param("c", 1.0, "affine c"), Param("d", 0.0, "affine d"), Param("e", 0.0, "affine e"),
    ) + SIZE_PARAMS

    intrinsic_names = ("pol", "invpol", "xc", "yc", "c", "d")

    @classmethod
    def scale(cls, v: dict[str, Any], sx: float, sy: float) -> dict[str, Any]:
        pol = parse_coefficients(cls.name, "pol", v["pol"])
        inv = parse_coefficients(cls.name, "invpol", v["invpol"])
        return {
            "pol": format_coefficients(pol * sx ** (1.0 - np.arange(pol.size))),
            "invpol": format_coefficients(inv * sx) if inv.size else "",
            "c": v["c"] * sy / sx, "d": v["d"] * sy / sx,
            "xc": (v["xc"] + 0.5) * sy - 0.5, "yc": (v["yc"] + 0.5) * sx - 0.5,
        }

    def _check(self) -> None:
        self.pol_c = parse_coefficients(self.name, "pol", self.pol)
        self.invpol_c = parse_coefficients(self.name, "invpol", self.invpol)
        self.pol, self.invpol = format_coefficients(self.pol_c), format_coefficients(self.invpol_c)  # one spelling
        if self.pol_c.size == 0 or not self.pol_c[0] < 0:
            raise LensError(f"{self.name}: pol must start with a negative a0 (OCamCalib looks down -z), got {self.pol!r}")
        det = self.c - self.d * self.e
        if det == 0:
            raise LensError(f"{self.name}: the affine matrix [[c, d], [e, 1]] is singular (c = d e)")
        self.invdet = 1.0 / det
        self.distortion = None
        # the end of the monotone range: rho pol'(rho) - pol(rho) = 0
        # the solve's bracket never needs to pass far beyond the image's farthest corner
        corners = np.array([[0, 0], [0, self.width], [self.height, 0], [self.height, self.width]], float) - 0.5
        xp, yp = self._affine_inverse(corners[:, 0], corners[:, 1])
        rho_cap = 4.0 * float(np.hypot(xp, yp).max()) + 1.0
        h = P.polysub(P.polymul([0.0, 1.0], P.polyder(self.pol_c)), self.pol_c)
        self.rho_fold = first_positive_root(h, rho_cap)
        self.rho_hi = min(self.rho_fold, rho_cap)
        self._angle_hi = float(self._angle(np.array([self.rho_hi]))[0][0])

    def _affine_inverse(self, row, col):
        r, c = row - self.xc, col - self.yc
        return self.invdet * (r - self.d * c), self.invdet * (-self.e * r + self.c * c)

    def _angle(self, rho):
        """Angle from the axis at radius ``rho`` and its derivative."""
        p = P.polyval(rho, self.pol_c)
        dp = P.polyval(rho, P.polyder(self.pol_c))
        return np.arctan2(rho, -p), (rho * dp - p) / (rho * rho + p * p)

    @property
    def solver_iterations(self) -> dict[str, int]:
        return {"d2p": getattr(self, "max_iterations", 0)}

    def pixel_to_dir(self, xy):
        xy = as_points(xy, 2, "pixel coordinates")
        shape = xy.shape[:-1]
        flat = xy.reshape(-1, 2)
        with np.errstate(all="ignore"):
            xp, yp = self._affine_inverse(flat[:, 1] - 0.5, flat[:, 0] - 0.5)  # (row, column), from 0
            rho = np.hypot(xp, yp)
            zp = P.polyval(rho, self.pol_c)
            ok = (rho < self.rho_fold) & np.isfinite(rho)
            d = np.empty(flat.shape[:-1] + (3,), dtype=FLOAT)
            # OCamCalib (x down, y right, z back) -> lenslab (right, up, forward) = (y, -x, -z), unit length
            d[:, 0], d[:, 1], d[:, 2] = unit_rows(yp, -xp, -zp)
        d, ok = clean(d, ok, inplace=True)
        return d.reshape(shape + (3,)), ok.reshape(shape)

    def dir_to_pixel(self, dirs):
        from lenslab.lenses.core.native import lens_kernels, run_rows

        d = as_points(dirs, 3, "directions")
        if getattr(self, "_table", None) is None:
            self._table = inverse_table(self._angle, self.rho_hi)
        table, step = self._table
        strict = bool(np.isfinite(self.rho_fold) and self.rho_hi == self.rho_fold)

        def fill(flat, xy, ok):
            self.max_iterations = lens_kernels().ocam_project(
                flat, self.pol_c * self.rho_hi ** (np.arange(self.pol_c.size) - 1.0), self.rho_hi, self._angle_hi, strict, table, step, *kernel_settings(),
                self.c, self.d, self.e, self.xc, self.yc, float(self.width), float(self.height), self.edge_slack, xy, ok)

        return run_rows(d, 2, fill)
