"""Compiled (numba) projections and inverses of the calibrated models.

The inverses use the one safeguarded Newton, :func:`lenslab.lenses.formulas.solve_kernels.solve_one`
(the steps and settings of :func:`lenslab.lenses.formulas.solve.invert_increasing`), on two families of
increasing maps with arbitrary coefficients:

- ``RATIONAL``: OpenCV's radial map ``r (1 + a1 r^2 + .. + a4 r^8) / (1 + b1 r^2 + b2 r^4 + b3 r^6)``
  (opencv, kannala-brandt on the angle, omnidir), followed, with tangential or thin-prism terms, by a
  2-D Newton on the whole distortion (steps halved to stay inside the fold);
- ``OCAM``: OCamCalib's angle from the axis ``atan2(rho, -pol(rho))`` reaching ``t``, solved as the
  root of ``rho cos(t) + pol(rho) sin(t)`` (the same sign as the angle minus ``t``; no arctangent).

Starting guesses come from a table of the inverse (``lenslab.lenses.formulas.solve.inverse_table``). Each
kernel returns the largest iteration count it needed (the benchmark states it).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from lenslab.lenses.formulas import calibrated_kernels as cp
from lenslab.lenses.formulas.kinds import DOUBLE_SPHERE, EQUIDISTANT, EUCM, FOV, RECTILINEAR, UNIFIED  # noqa: F401
from lenslab.lenses.formulas.solve import OCAM, RATIONAL
from lenslab.lenses.formulas.solve_kernels import rational_radial, solve_one, table_guess

#: the pinhole is the rectilinear projection (:mod:`lenslab.lenses.formulas.kinds` holds the codes)
PINHOLE = RECTILINEAR

JIT = dict(cache=True, error_model="numpy")


@numba.njit(inline="always", **JIT)
def _distort(x, y, a, b, p1, p2, s):
    """OpenCV's distortion of one point and its Jacobian."""
    r2 = x * x + y * y
    R, dR = rational_radial(math.sqrt(r2), a, b)
    xd = x * R + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x) + s[0] * r2 + s[1] * r2 * r2
    yd = y * R + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y + s[2] * r2 + s[3] * r2 * r2
    dsx = s[0] + 2.0 * s[1] * r2
    dsy = s[2] + 2.0 * s[3] * r2
    j11 = R + 2.0 * x * x * dR + 2.0 * p1 * y + 6.0 * p2 * x + 2.0 * x * dsx
    j12 = 2.0 * x * y * dR + 2.0 * p1 * x + 2.0 * p2 * y + 2.0 * y * dsx
    j21 = 2.0 * x * y * dR + 2.0 * p1 * x + 2.0 * p2 * y + 2.0 * x * dsy
    j22 = R + 2.0 * y * y * dR + 6.0 * p1 * y + 2.0 * p2 * x + 2.0 * y * dsy
    return xd, yd, j11, j12, j21, j22


@numba.njit(inline="always", **JIT)
def _undistort(xd, yd, a, b, p1, p2, s, tangential, fold, hi, f_hi, strict, table, tstep,
               tol, res_tol, rel_ulps, max_iter, tol_2d, max_iter_2d):
    """Undistort one point of the normalised plane: ``(ok, x, y, iterations)`` (1-D + 2-D)."""
    fold2 = fold * fold
    rd = math.sqrt(xd * xd + yd * yd)
    h2 = hi * hi  # tangential and prism terms move a point by at most this inside the bracket: a distorted
    # radius up to f_hi plus that can come from a valid point near the fold
    lim = f_hi + ((3.0 * (abs(p1) + abs(p2)) + abs(s[0]) + abs(s[2])) * h2 + (abs(s[1]) + abs(s[3])) * h2 * h2
                  if tangential else 0.0)
    if not ((rd < lim) if strict else (rd <= lim)):  # also False for NaN
        return False, 0.0, 0.0, 0
    # the radial solve starts the 2-D one; beyond the radial map's reach it starts at the fold's edge
    rr = rd if rd < f_hi else f_hi * (1.0 - 1e-9)
    r, ok, its = solve_one(RATIONAL, a, b, rr, hi, table_guess(rr, table, tstep, False), tol, res_tol, rel_ulps, max_iter)
    if not ok or (strict and not r < fold):
        return False, 0.0, 0.0, its
    x = xd * (r / rd) if rd > 0.0 else xd
    y = yd * (r / rd) if rd > 0.0 else yd
    if not tangential:
        return True, x, y, its
    ok = False
    it2 = 0
    for it2 in range(1, max_iter_2d + 1):
        fx, fy, j11, j12, j21, j22 = _distort(x, y, a, b, p1, p2, s)
        ex = fx - xd
        ey = fy - yd
        if math.sqrt(ex * ex + ey * ey) <= tol_2d * max(1.0, rd):
            ok = True
            break
        det = j11 * j22 - j12 * j21
        sx = (j22 * ex - j12 * ey) / det
        sy = (j11 * ey - j21 * ex) / det
        step = 1.0
        for _ in range(30):  # halve the step until it stays inside the fold
            if (x - step * sx) ** 2 + (y - step * sy) ** 2 < fold2:
                break
            step *= 0.5
        x -= step * sx
        y -= step * sy
    if ok:
        _, _, j11, j12, j21, j22 = _distort(x, y, a, b, p1, p2, s)
        ok = j11 * j22 - j12 * j21 > 0.0 and x * x + y * y < fold2
    return ok, x, y, its + it2


@numba.njit(inline="always", **JIT)
def _cv_ray(d, i, out, valid):
    """Direction ``i`` (lenslab's frame, any length) as a unit ray in OpenCV's frame (y down), and
    whether it is one (finite, non-zero); clears the outputs of element ``i``."""
    out[i, 0] = 0.0
    out[i, 1] = 0.0
    valid[i] = False
    X = d[i, 0]
    Y = -d[i, 1]
    Z = d[i, 2]
    n2 = X * X + Y * Y + Z * Z
    if not (n2 > 0.0 and n2 < math.inf):
        return False, 0.0, 0.0, 1.0
    inv = 1.0 / math.sqrt(n2)
    return True, X * inv, Y * inv, Z * inv


@numba.njit(**JIT)
def ocam_project_kernel(d, pol_unit, hi, a_hi, strict, table, tstep, tol, res_tol, rel_ulps, max_iter,
                        c, dd, e, xc, yc, width, height, slack, out, valid):
    """OCamCalib, lenslab directions -> lenslab pixels: the radius ``rho`` whose ray is the direction's
    angle from the axis (solved), then ``row = c xp + d yp + xc``, ``col = e xp + yp + yc`` (OCamCalib's
    ``xp`` along rows = lenslab's ``-y``, ``yp`` along columns = ``x``); the largest iteration count."""
    cs = np.zeros(3)
    worst = 0
    for i in range(d.shape[0]):
        ok, X, Y, Z = _cv_ray(d, i, out, valid)
        if not ok:
            continue
        lat = math.sqrt(X * X + Y * Y)
        t = math.atan2(lat, Z)
        if not ((t < a_hi) if strict else (t <= a_hi)):
            continue
        cs[0] = math.cos(t)
        cs[1] = math.sin(t)
        # solved for u = rho / hi in [0, 1] with pol_unit(u) = pol(u hi) / hi: dimensionless, so the
        # tolerances mean what they mean for the other solves
        u, ok, its = solve_one(OCAM, pol_unit, cs, 0.0, 1.0, table_guess(t, table, tstep, False) / hi, tol, res_tol,
                            rel_ulps, max_iter)
        rho = u * hi
        if not ok:
            continue
        worst = max(worst, its)
        k = rho / lat if lat > 0.0 else 0.0
        xp = Y * k
        yp = X * k
        _store(i, e * xp + yp + yc + 0.5, c * xp + dd * yp + xc + 0.5, width, height, slack, out, valid)  # col, row
    return worst


@numba.njit(**JIT)
def distort_kernel(x, y, a, b, p1, p2, s, tangential, fold, out_x, out_y, valid):
    """OpenCV's distortion of points inside the fold (with a positive Jacobian when tangential)."""
    fold2 = fold * fold
    for i in range(x.shape[0]):
        xi = x[i]
        yi = y[i]
        ok = xi * xi + yi * yi < fold2
        if ok:
            xd, yd, j11, j12, j21, j22 = _distort(xi, yi, a, b, p1, p2, s)
            if tangential:
                ok = j11 * j22 - j12 * j21 > 0.0
        if ok:
            out_x[i] = xd
            out_y[i] = yd
        else:
            out_x[i] = 0.0
            out_y[i] = 0.0
        valid[i] = ok


@numba.njit(inline="always", **JIT)
def _store(i, u, v, width, height, slack, out, valid):
    """Pixel ``i`` if inside the image (within ``slack`` px of it counts, moved onto the edge)."""
    if u >= -slack and u <= width + slack and v >= -slack and v <= height + slack:
        out[i, 0] = min(max(u, 0.0), width)
        out[i, 1] = min(max(v, 0.0), height)
        valid[i] = True


# -- direction -> pixel, fused: projection, distortion, intrinsics, image test -------------------------


@numba.njit(**JIT)
def project_kernel(d, kind, q, a, b, p1, p2, s, distort, tangential, fold, fx, fy, skew, cx, cy, width, height,
                   slack, out, valid):
    """lenslab directions (any length) -> lenslab pixels of a calibrated model, with validity.

    ``kind`` picks the projection to the normalised plane (in OpenCV's frame ``X, -Y, Z``) with its
    parameters ``q``: PINHOLE ``X/Z``; FOV ``X/Z`` scaled to ``r_d = atan(2 r_u tan(omega/2)) / omega``,
    ``q = (omega, 2 tan(omega/2))``; EQUIDISTANT ``theta (X, Y)/rho``; UNIFIED (Mei) ``X/(Z + xi)``,
    ``q = (xi, w)``; DOUBLE_SPHERE ``q = (xi, alpha, w2)``; EUCM ``q = (alpha, beta, w)``. Then OpenCV's
    distortion (inside the fold, positive Jacobian), ``u = fx x + skew y + cx + 0.5``, ``v = fy y + cy + 0.5``
    and the image test (within ``slack`` px of the edges counts, moved onto them)."""
    fold2 = fold * fold
    for i in range(d.shape[0]):
        ok, X, Y, Z = _cv_ray(d, i, out, valid)
        if not ok:
            continue
        mx, my, seen = cp.project_one(kind, X, Y, Z, q)
        if not seen:
            continue
        if distort:
            if not mx * mx + my * my < fold2:
                continue
            mx, my, j11, j12, j21, j22 = _distort(mx, my, a, b, p1, p2, s)
            if tangential and not j11 * j22 - j12 * j21 > 0.0:
                continue
        _store(i, fx * mx + skew * my + cx + 0.5, fy * my + cy + 0.5, width, height, slack, out, valid)


@numba.njit(**JIT)
def unproject_kernel(xy, kind, q, a, b, p1, p2, s, distort, tangential, fold, hi, f_hi, strict, table, tstep,
                     tol, res_tol, rel_ulps, max_iter, tol_2d, max_iter_2d, fx, fy, skew, cx, cy, out, valid):
    """lenslab pixels -> lenslab unit directions of a calibrated model, with validity: OpenCV's pixel
    ``(x - 0.5, y - 0.5)``, the inverse intrinsics, undistortion (solved) and the projection's closed-form
    inverse (``kind`` and ``q`` as for :func:`project_kernel`). Returns the largest iteration count of the
    points whose solve converged (the others are invalid)."""
    worst = 0
    for i in range(xy.shape[0]):
        out[i, 0] = 0.0
        out[i, 1] = 0.0
        out[i, 2] = 0.0
        valid[i] = False
        my = (xy[i, 1] - 0.5 - cy) / fy
        mx = (xy[i, 0] - 0.5 - cx - skew * my) / fx
        if not (math.isfinite(mx) and math.isfinite(my)):
            continue
        if distort:
            ok, mx, my, its = _undistort(mx, my, a, b, p1, p2, s, tangential, fold, hi, f_hi, strict, table, tstep,
                                         tol, res_tol, rel_ulps, max_iter, tol_2d, max_iter_2d)
            if not ok:
                continue
            worst = max(worst, its)
        X, Y, Z, seen = cp.unproject_one(kind, mx, my, q)
        if not seen:
            continue
        out[i, 0] = X
        out[i, 1] = -Y  # OpenCV's y down -> lenslab's y up
        out[i, 2] = Z
        valid[i] = True
    return worst
