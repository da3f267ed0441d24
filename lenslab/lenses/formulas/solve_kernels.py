"""Compiled (numba) safeguarded Newton for the radial maps of the lens models.

The per-element loop of :func:`lenslab.lenses.formulas.solve.invert_increasing`, one element at a time: no
temporary arrays and no compaction of the active set. The fused kernels below also do the model's
work around the solve (radius, range test, starting guess, rescaling) in the same pass, which is what
makes the numerically inverted sides of the distortion and tan-fold fisheye models fast. Imported on first
use (numba's import and the cached compilation stay out of ``import lenslab``).

Starting guesses come from a table of the inverse sampled at uniform steps of ``g(target)``
(``g`` = identity, or square root for the tan-fold fisheye, whose angle grows as ``F r^2`` at the centre),
linearly interpolated: a guess within ~1e-6, which Newton turns into the root in two or three steps.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from lenslab.lenses.formulas.solve import BROWN, DIVISION, DIVISION_RECIPROCAL, OCAM, RATIONAL, TAN_FISHEYE

JIT = dict(cache=True, error_model="numpy")


@numba.njit(inline="always", **JIT)
def rational_radial(r, a, b):
    """``R(r)`` and ``dR/d(r^2)`` of OpenCV's rational radial factor
    ``(1 + a1 r^2 + .. + a4 r^8) / (1 + b1 r^2 + b2 r^4 + b3 r^6)``."""
    s = r * r
    num = 1.0 + s * (a[0] + s * (a[1] + s * (a[2] + s * a[3])))
    dnum = a[0] + s * (2.0 * a[1] + s * (3.0 * a[2] + s * 4.0 * a[3]))
    den = 1.0 + s * (b[0] + s * (b[1] + s * b[2]))
    dden = b[0] + s * (2.0 * b[1] + s * 3.0 * b[2])
    return num / den, (dnum * den - num * dden) / (den * den)


@numba.njit(inline="always", **JIT)
def radial_value(kind, x, a, b):
    """Value and derivative of radial map ``kind`` (:mod:`lenslab.lenses.formulas.solve`'s codes) at
    ``x``; ``a`` and ``b`` are its coefficient arrays (``a = (k1, k2)`` for the two-coefficient maps)."""
    if kind == RATIONAL:
        R, dR = rational_radial(x, a, b)
        return x * R, R + 2.0 * x * x * dR
    if kind == OCAM:
        p = 0.0
        dp = 0.0
        for j in range(a.shape[0] - 1, -1, -1):  # Horner for pol and its derivative
            dp = dp * x + p
            p = p * x + a[j]
        # rho cos(t) + pol(rho) sin(t) = |(rho, -pol)| sin(angle(rho) - t): the sign of angle(rho) - t with
        # no arctangent; b = (cos t, sin t)
        return x * b[0] + p * b[1], b[0] + dp * b[1]
    p0 = a[0]
    p1 = a[1]
    s = x * x
    if kind == DIVISION or kind == DIVISION_RECIPROCAL:
        den = 1.0 + s * (p0 + p1 * s)
        num = 1.0 - s * (p0 + 3.0 * p1 * s)
        if kind == DIVISION:
            if den <= 0.0:
                return math.inf, 0.0  # at and past a pole r_u is +inf
            return x / den, num / (den * den)
        if x == 0.0:
            return -math.inf, math.inf
        return -den / x, num / s
    if kind == BROWN:
        return x * (1.0 + s * (p0 + p1 * s)), 1.0 + s * (3.0 * p0 + 5.0 * p1 * s)
    # TAN_FISHEYE: the tan-fold fisheye's angle from the axis, kept increasing past the fold
    t = math.tan(x * p0)
    st = math.sin(t)
    ct = math.cos(t)
    y = x * st
    psi = math.atan2(y, ct)
    if y < 0.0:
        psi += 2.0 * math.pi
    return psi, (st * ct + x * p0 * (1.0 + t * t)) / (ct * ct + y * y)


@numba.njit(inline="always", **JIT)
def solve_one(kind, a, b, t, hi, x0, tol, res_tol, rel_ulps, max_iter):
    """Safeguarded Newton for one element on ``[0, hi]``: ``(x, converged, iterations)``; the steps of
    :func:`lenslab.lenses.formulas.solve.invert_increasing`, the one loop of every compiled solve."""
    lo_b = 0.0
    hi_b = hi
    x = min(max(x0, lo_b), hi_b)
    last_step = math.inf
    for it in range(1, max_iter + 1):
        fx, dfx = radial_value(kind, x, a, b)
        res = fx - t
        if res < 0.0:
            lo_b = x
        else:
            hi_b = x
        xn = x - res / dfx
        step = abs(xn - x)
        small = step <= tol
        far = abs(res) > res_tol * max(1.0, abs(t))
        bad = not (xn >= lo_b and xn <= hi_b) or (small and far) or step > 0.5 * last_step
        if bad:
            xn = 0.5 * (lo_b + hi_b)
        at_rounding = abs(res) <= rel_ulps * abs(t)
        done = (small and not bad) or at_rounding or (hi_b - lo_b <= tol)
        if at_rounding:
            xn = x
        last_step = abs(xn - x)
        x = xn
        if done:
            return x, True, it
    return x0, False, max_iter


@numba.njit(inline="always", **JIT)
def table_guess(t, table, step, sqrt_map):
    """Linear interpolation in the table of the inverse (uniform in t, or in sqrt(t))."""
    g = math.sqrt(t) if sqrt_map else t
    q = g / step
    n = table.shape[0] - 1
    if not q < n:  # beyond the table (or NaN): its last entry, Newton does the rest
        return table[n]
    j = int(q)
    w = q - j
    return table[j] + w * (table[j + 1] - table[j])



@numba.njit(**JIT)
def division_unbend(uv, k1, k2, hi, f_hi, strict, pole, table, tstep, tol, res_tol, rel_ulps, max_iter,
                    out, valid):
    """Division model, direction side: undistorted ``(u, v)`` (radius r_u) -> image ``(u, v)``."""
    ab = np.array([k1, k2])
    for i in range(uv.shape[0]):
        u = uv[i, 0]
        v = uv[i, 1]
        t = math.sqrt(u * u + v * v)
        inside = (t < f_hi) if strict else (t <= f_hi)
        ok = False
        x = 0.0
        if inside:
            x0 = table_guess(t, table, tstep, False)
            if pole and t > 1.0:
                x, ok, _ = solve_one(DIVISION_RECIPROCAL, ab, ab, -1.0 / t, hi, x0, tol, res_tol, rel_ulps, max_iter)
            else:
                x, ok, _ = solve_one(DIVISION, ab, ab, t, hi, x0, tol, res_tol, rel_ulps, max_iter)
        if ok:
            s = x * x
            den = 1.0 + s * (k1 + k2 * s)  # r_d / r_u, with the limit 1 at the centre
            out[i, 0] = u * den
            out[i, 1] = v * den
        else:
            out[i, 0] = 0.0
            out[i, 1] = 0.0
        valid[i] = ok


@numba.njit(**JIT)
def brown_bend(uv, k1, k2, hi, rd_fold, table, tstep, tol, res_tol, rel_ulps, max_iter, out, valid):
    """Brown polynomial, pixel side: image ``(u, v)`` (radius r_d) -> undistorted ``(u, v)``."""
    ab = np.array([k1, k2])
    for i in range(uv.shape[0]):
        u = uv[i, 0]
        v = uv[i, 1]
        t = math.sqrt(u * u + v * v)
        ok = False
        x = 0.0
        if t < rd_fold:
            x, ok, _ = solve_one(BROWN, ab, ab, t, hi, table_guess(t, table, tstep, False), tol, res_tol, rel_ulps, max_iter)
        if ok:
            scale = x / t if t > 0.0 else 1.0
            out[i, 0] = u * scale
            out[i, 1] = v * scale
        else:
            out[i, 0] = 0.0
            out[i, 1] = 0.0
        valid[i] = ok


@numba.njit(**JIT)
def tan_fisheye_dir_to_uv(d, F, hi, psi_max, strict, table, tstep, tol, res_tol, rel_ulps, max_iter, out, valid):
    """Tan-fold fisheye, direction side: unit direction -> ``(u, v)``."""
    ab = np.array([F, 0.0])
    for i in range(d.shape[0]):
        dx = d[i, 0]
        dy = d[i, 1]
        rho = math.sqrt(dx * dx + dy * dy)
        theta = math.atan2(rho, d[i, 2])
        inside = (theta < psi_max) if strict else (theta <= psi_max)
        ok = False
        x = 0.0
        if inside:
            x, ok, _ = solve_one(TAN_FISHEYE, ab, ab, theta, hi, table_guess(theta, table, tstep, True), tol, res_tol, rel_ulps,
                           max_iter)
        if ok and rho > 0.0:
            k = x / rho
            out[i, 0] = dx * k
            out[i, 1] = dy * k
        else:
            out[i, 0] = 0.0
            out[i, 1] = 0.0
        valid[i] = ok
