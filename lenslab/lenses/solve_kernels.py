"""Compiled (numba) safeguarded Newton for the radial maps of the lens models.

The per-element loop of :func:`lenslab.lenses.solve.invert_increasing`, one element at a time: no
temporary arrays and no compaction of the active set. The fused kernels below also do the model's
work around the solve (radius, range test, starting guess, rescaling) in the same pass, which is what
makes the numerically inverted sides of the distortion and seed-fisheye models fast. Imported on first
use (numba's import and the cached compilation stay out of ``import lenslab``).

Starting guesses come from a table of the inverse sampled at uniform steps of ``g(target)``
(``g`` = identity, or square root for the seed fisheye, whose angle grows as ``F r^2`` at the centre),
linearly interpolated: a guess within ~1e-6, which Newton turns into the root in two or three steps.
"""

from __future__ import annotations

import math

import numba

JIT = dict(cache=True, error_model="numpy")


@numba.njit(inline="always", **JIT)
def _radial(kind, x, p0, p1):
    """Value and derivative of radial map ``kind`` at ``x`` (the models' compiled inverses)."""
    s = x * x
    if kind == 0 or kind == 1:  # division model
        den = 1.0 + s * (p0 + p1 * s)
        num = 1.0 - s * (p0 + 3.0 * p1 * s)
        if kind == 0:
            if den <= 0.0:
                return math.inf, 0.0  # at and past a pole r_u is +inf
            return x / den, num / (den * den)
        if x == 0.0:
            return -math.inf, math.inf
        return -den / x, num / s
    if kind == 2:  # Brown polynomial
        return x * (1.0 + s * (p0 + p1 * s)), 1.0 + s * (3.0 * p0 + 5.0 * p1 * s)
    # the seed fisheye's angle from the axis, kept increasing past the fold
    t = math.tan(x * p0)
    st = math.sin(t)
    ct = math.cos(t)
    y = x * st
    psi = math.atan2(y, ct)
    if y < 0.0:
        psi += 2.0 * math.pi
    return psi, (st * ct + x * p0 * (1.0 + t * t)) / (ct * ct + y * y)


@numba.njit(inline="always", **JIT)
def _solve(kind, p0, p1, t, hi, x0, tol, res_tol, rel_ulps, max_iter):
    """Safeguarded Newton for one element: ``(x, converged)``; same steps as invert_increasing."""
    a = 0.0
    b = hi
    x = min(max(x0, a), b)
    last_step = math.inf
    for _ in range(max_iter):
        fx, dfx = _radial(kind, x, p0, p1)
        res = fx - t
        if res < 0.0:
            a = x
        else:
            b = x
        xn = x - res / dfx
        step = abs(xn - x)
        small = step <= tol
        far = abs(res) > res_tol * max(1.0, abs(t))
        bad = not (xn >= a and xn <= b) or (small and far) or step > 0.5 * last_step
        if bad:
            xn = 0.5 * (a + b)
        at_rounding = abs(res) <= rel_ulps * abs(t)
        done = (small and not bad) or at_rounding or (b - a <= tol)
        if at_rounding:
            xn = x
        last_step = abs(xn - x)
        x = xn
        if done:
            return x, True
    return x0, False


@numba.njit(inline="always", **JIT)
def _guess(t, table, step, sqrt_map):
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
    for i in range(uv.shape[0]):
        u = uv[i, 0]
        v = uv[i, 1]
        t = math.sqrt(u * u + v * v)
        inside = (t < f_hi) if strict else (t <= f_hi)
        ok = False
        x = 0.0
        if inside:
            x0 = _guess(t, table, tstep, False)
            if pole and t > 1.0:
                x, ok = _solve(1, k1, k2, -1.0 / t, hi, x0, tol, res_tol, rel_ulps, max_iter)
            else:
                x, ok = _solve(0, k1, k2, t, hi, x0, tol, res_tol, rel_ulps, max_iter)
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
    for i in range(uv.shape[0]):
        u = uv[i, 0]
        v = uv[i, 1]
        t = math.sqrt(u * u + v * v)
        ok = False
        x = 0.0
        if t < rd_fold:
            x, ok = _solve(2, k1, k2, t, hi, _guess(t, table, tstep, False), tol, res_tol, rel_ulps, max_iter)
        if ok:
            scale = x / t if t > 0.0 else 1.0
            out[i, 0] = u * scale
            out[i, 1] = v * scale
        else:
            out[i, 0] = 0.0
            out[i, 1] = 0.0
        valid[i] = ok


@numba.njit(**JIT)
def seed_dir_to_uv(d, F, hi, psi_max, strict, table, tstep, tol, res_tol, rel_ulps, max_iter, out, valid):
    """Seed fisheye, direction side: unit direction -> ``(u, v)``."""
    for i in range(d.shape[0]):
        dx = d[i, 0]
        dy = d[i, 1]
        rho = math.sqrt(dx * dx + dy * dy)
        theta = math.atan2(rho, d[i, 2])
        inside = (theta < psi_max) if strict else (theta <= psi_max)
        ok = False
        x = 0.0
        if inside:
            x, ok = _solve(3, F, 0.0, theta, hi, _guess(theta, table, tstep, True), tol, res_tol, rel_ulps,
                           max_iter)
        if ok and rho > 0.0:
            k = x / rho
            out[i, 0] = dx * k
            out[i, 1] = dy * k
        else:
            out[i, 0] = 0.0
            out[i, 1] = 0.0
        valid[i] = ok
