"""OpenCV's distortion polynomial on a normalised plane, forward in closed form and inverted by Newton.

One implementation serves every calibrated model that distorts a projected point ``(x, y)`` (kornia's
"projection composed with distortion"): ``opencv`` (pinhole plane), ``kannala-brandt`` (the
equidistant plane, where ``r`` is the angle from the axis) and ``omnidir`` (Mei's unified plane).
With ``r^2 = x^2 + y^2``::

    R(r)  = (1 + a1 r^2 + a2 r^4 + a3 r^6 + a4 r^8) / (1 + b1 r^2 + b2 r^4 + b3 r^6)
    x_d   = x R + 2 p1 x y + p2 (r^2 + 2 x^2) + s1 r^2 + s2 r^4
    y_d   = y R + p1 (r^2 + 2 y^2) + 2 p2 x y + s3 r^2 + s4 r^4

which is ``cv2.projectPoints``'s (``a = k1, k2, k3``, ``b = k4, k5, k6``) and ``cv2.fisheye``'s
(``a = k1..k4`` on the angle). The lens folds where the radial map ``r R(r)`` stops increasing: its
derivative's numerator is a polynomial in ``r^2`` whose first positive root (or the denominator's) is
the fold radius. Points at or beyond it are invalid both ways, and so are points where the Jacobian of
the whole map is not positive (the tangential and prism terms can fold it too).

The inverse (compiled: ``lenslab.cxx_kernels``, ``src/native/lens_solved.cpp``): the radius is solved by the
safeguarded Newton of :func:`lenslab.lenses.formulas.solve.invert_increasing` from a table of the inverse;
with tangential or prism terms that radial solution starts a 2-D Newton on the whole map, steps halved
until they stay inside the fold radius, at most :data:`MAX_ITER_2D` iterations, converged when the
residual is below :data:`TOL_2D`. Near the fold those terms carry valid points a little beyond the
radial map's largest radius (by at most ``3 (|p1| + |p2|) r^2 + (|s1| + |s3|) r^2 + (|s2| + |s4|) r^4``
at the bracket's radius): such a point starts its 2-D solve at the fold's edge instead of being refused,
so every pixel the forward map reaches is inverted. Points that do not converge are invalid, never returned as if they had.
"""

from __future__ import annotations

import functools

import numpy as np
from numpy.polynomial import polynomial as P

from lenslab.lenses.formulas.solve import inverse_table

FLOAT = np.float64
#: residual of the 2-D solve in normalised units (1e-14 of the focal length: 1e-11 px at f = 1000 px)
TOL_2D = 1e-14
MAX_ITER_2D = 40


def first_positive_root(coeffs, s_max: float = np.inf) -> float:
    """Smallest positive ``s <= s_max`` where the polynomial ``sum c_i s^i`` (positive at 0) changes sign
    (``inf`` if none). Found by sampling (dense up to 10, geometric beyond, to 1e6 when ``s_max`` is
    infinite) and bisection to the last bit: robust where eigenvalue root finders are not (a
    negligible leading coefficient throws ``polyroots`` off)."""
    c = np.asarray(coeffs, dtype=FLOAT)
    grid = _root_grid(min(float(s_max), 1e6))
    vals = P.polyval(grid, c)
    sign0 = np.sign(vals[0]) or 1.0
    bad = np.flatnonzero(np.sign(vals) != sign0)
    if bad.size == 0:
        return np.inf
    lo, hi = float(grid[bad[0] - 1]), float(grid[bad[0]])
    terms = c[::-1].tolist()  # highest first: Horner's rule in Python floats, as polyval does it

    def value(x: float) -> float:
        v = terms[0] + x * 0.0
        for t in terms[1:]:
            v = t + v * x
        return v

    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        if np.sign(value(mid)) == sign0:
            lo = mid
        else:
            hi = mid
    return hi


@functools.lru_cache(maxsize=32)
def _root_grid(top: float) -> np.ndarray:
    """The samples of :func:`first_positive_root` up to ``top`` (read-only; made once per bound)."""
    grid = np.linspace(0.0, min(top, 10.0), 4001)
    if top > 10.0:
        grid = np.concatenate([grid, np.geomspace(10.0, top, 2001)[1:]])
    grid.flags.writeable = False
    return grid


class PolyDistortion:
    """The distortion polynomial with numerator ``a`` (up to 4 terms), denominator ``b`` (up to 3),
    tangential ``p1, p2`` and thin prism ``s1..s4``; ``limit`` bounds the undistorted radius (the
    projection's own range, e.g. pi on the equidistant plane)."""

    def __init__(self, a=(), b=(), p1=0.0, p2=0.0, s=(0.0, 0.0, 0.0, 0.0), limit=np.inf):
        self.a = np.array(list(a) + [0.0] * (4 - len(a)), dtype=FLOAT)
        self.b = np.array(list(b) + [0.0] * (3 - len(b)), dtype=FLOAT)
        self.p1, self.p2 = float(p1), float(p2)
        self.s = np.array(list(s) + [0.0] * (4 - len(s)), dtype=FLOAT)
        self.radial_only = self.p1 == 0 and self.p2 == 0 and not self.s.any()
        self.identity = self.radial_only and not self.a.any() and not self.b.any()
        self.limit = float(limit)
        self.fold = min(self._fold_radius(), self.limit)  # undistorted radius bound (may be inf)
        self.max_iterations = 0  # largest iteration count of the last inverse (for the benchmark)
        self.table, self.rd_max = None, 1.0  # (the inverse: made on first use, see prepare)

    # -- the radial map -------------------------------------------------------------------------
    def _fold_radius(self) -> float:
        """First radius where ``d(r R)/dr`` reaches 0 or the denominator vanishes."""
        n = np.r_[1.0, self.a]
        s_max = self.limit * self.limit
        if not self.b.any():  # no denominator: N + 2 s N', the same coefficients polymul and polyadd give
            return float(np.sqrt(first_positive_root(n + 2.0 * (np.arange(n.size, dtype=FLOAT) * n), s_max)))
        d = np.r_[1.0, self.b]
        s_poly = np.array([0.0, 1.0])
        # d/dr [r N(s)/D(s)] with s = r^2 has numerator (N + 2 s N') D - 2 s N D'
        num = P.polysub(P.polymul(P.polyadd(n, 2.0 * P.polymul(s_poly, P.polyder(n))), d),
                        2.0 * P.polymul(s_poly, P.polymul(n, P.polyder(d))))
        s_fold = min(first_positive_root(num, s_max), first_positive_root(d, s_max))
        return float(np.sqrt(s_fold))

    def radial(self, r2):
        """``R`` and ``dR/d(r^2)`` at squared radii (float64 arrays)."""
        a, b = self.a, self.b
        num = 1.0 + r2 * (a[0] + r2 * (a[1] + r2 * (a[2] + r2 * a[3])))
        dnum = a[0] + r2 * (2.0 * a[1] + r2 * (3.0 * a[2] + r2 * 4.0 * a[3]))
        if not b.any():
            return num, dnum
        den = 1.0 + r2 * (b[0] + r2 * (b[1] + r2 * b[2]))
        dden = b[0] + r2 * (2.0 * b[1] + r2 * 3.0 * b[2])
        return num / den, (dnum * den - num * dden) / (den * den)

    def radius_map(self, r):
        """``r R(r)`` and its derivative, for the radial solve."""
        r2 = r * r
        R, dR = self.radial(r2)
        return r * R, R + 2.0 * r2 * dR

    # -- forward ---------------------------------------------------------------------------------
    def apply(self, x, y):
        """Distorted ``(x_d, y_d)`` and validity (inside the fold, positive Jacobian); compiled."""
        from lenslab.lenses.core.native import lens_kernels

        x = np.ascontiguousarray(x, dtype=FLOAT)
        y = np.ascontiguousarray(y, dtype=FLOAT)
        if self.identity:
            return x.copy(), y.copy(), x * x + y * y < self.fold * self.fold
        xd = np.empty_like(x)
        yd = np.empty_like(y)
        valid = np.empty(x.shape, dtype=np.bool_)
        lens_kernels().distort_points(x, y, self.a, self.b, self.p1, self.p2, self.s, not self.radial_only, self.fold, xd, yd, valid)
        return xd, yd, valid

    # -- inverse ---------------------------------------------------------------------------------
    def prepare(self, rd_max: float) -> None:
        """Set up the inverse for distorted radii up to ``rd_max`` (the image's farthest corner, with a
        margin): the bracket of the radial solve and its table of starting guesses, made on first use
        (:meth:`ready`), so a lens only projected (a fit's evaluations in pixel space) never makes them."""
        self.rd_max, self.table = float(rd_max), None

    def ready(self) -> "PolyDistortion":
        """This distortion with its inverse set up (see :meth:`prepare`)."""
        if self.table is None:
            self._make_inverse(self.rd_max)
        return self

    def _make_inverse(self, rd_max: float) -> None:
        hi = self.fold
        if not np.isfinite(hi):  # no fold: a bracket wide enough for every radius in the image
            hi = max(float(rd_max), 1e-3)
            while self.radius_map(np.array([hi]))[0][0] < rd_max and hi < 1e12:
                hi *= 2.0
        self.hi = hi
        self.f_hi = float(self.radius_map(np.array([hi]))[0][0])
        self.strict = bool(np.isfinite(self.fold))
        self.table = inverse_table(self.radius_map, hi)  # (last: a table set means the rest is)
