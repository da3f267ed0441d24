"""Numeric inversion of increasing radial functions: safeguarded Newton with a bracket.

Several lens models map a radius to a radius (or an angle) by a function with no closed-form
inverse: the division model of radial distortion, the Brown polynomial's pixel -> direction side and
the seed's legacy fisheye. :func:`invert_increasing` solves ``f(x) = target`` for whole arrays at once.
Each element keeps a bracket ``[lo, hi]`` that always holds the root; a Newton step that leaves the
bracket (or meets a zero or negative slope) is replaced by bisection, so convergence is guaranteed for
a continuous increasing ``f``. Elements stop as soon as they meet the convergence test; those
still running after ``max_iter`` iterations are reported as not converged (the callers flag them
invalid), never returned silently.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

FLOAT = np.float64

#: absolute tolerance on the solved radius (normalised units: 1 = half the image width). At 8192 px
#: width one pixel is 2.4e-4 units, so 1e-13 is 4e-10 px; the last Newton step is quadratic, so the
#: returned value is usually far closer than that.
TOL = 1e-13
MAX_ITER = 100
EPS = float(np.finfo(np.float64).eps)
#: a residual within this many ulps (units of EPS * |target|) of the target counts as solved: evaluating f takes a handful of
#: roundings, so its value is no more exact than that (next to a fold, where the slope is small, this
#: is the test that ends the solve: the root is then pinned as well as float64 allows)
RESIDUAL_ULPS = 8.0
#: a Newton step below ``tol`` only counts when the residual is below this (relative to the target
#: beyond 1): the solves must meet 1e-10 in the value of f
RESIDUAL_TOL = 1e-11


def invert_increasing(
    f: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]],
    target: np.ndarray,
    lo,
    hi,
    x0: np.ndarray,
    tol: float = TOL,
    max_iter: int = MAX_ITER,
) -> tuple[np.ndarray, np.ndarray]:
    """Solve ``f(x) = target`` elementwise on ``[lo, hi]`` for an increasing ``f``.

    ``f(x)`` returns ``(value, derivative)`` for a 1-D float64 array ``x``. ``target`` and ``x0`` are
    1-D float64 arrays of one length; ``lo`` and ``hi`` are scalars or arrays of that length with
    ``f(lo) <= target <= f(hi)`` (the caller checks this and flags other elements itself).
    Returns ``(x, converged)``. An element has converged when its Newton step falls below ``tol``
    with a residual below ``RESIDUAL_TOL`` (1e-11, relative beyond 1),
    when its residual ``f(x) - target`` is within 8 ulps of ``target`` (float64 can do no better;
    next to a fold, where the slope vanishes, this is the binding test), or when its bracket is
    narrower than ``tol``. Elements still running after ``max_iter`` iterations are reported False.
    """
    target = np.asarray(target, dtype=FLOAT)
    n = target.shape[0]
    a = np.array(np.broadcast_to(np.asarray(lo, dtype=FLOAT), (n,)))
    b = np.array(np.broadcast_to(np.asarray(hi, dtype=FLOAT), (n,)))
    x = np.clip(np.asarray(x0, dtype=FLOAT), a, b)
    out = x.copy()
    converged = np.zeros(n, dtype=bool)
    idx = np.arange(n)
    t = target
    last_step = np.full(n, np.inf)  # the first Newton step is only bounded by the bracket
    with np.errstate(all="ignore"):
        for _ in range(max_iter):
            if idx.size == 0:
                break
            fx, dfx = f(x)
            res = fx - t
            below = res < 0
            a = np.where(below, x, a)
            b = np.where(below, b, x)
            xn = x - res / dfx
            # a step that leaves the bracket (or a NaN/inf step from a flat or wrong-way slope) bisects,
            # and so does a vanishing step with a large residual: next to a pole of f Newton's steps
            # shrink to nothing far from the root
            # (and, as in Numerical Recipes' rtsafe, a step not at least halving the one before it:
            # that is Newton ping-ponging across an inflection, which bisection ends)
            step = np.abs(xn - x)
            small = step <= tol
            far = np.abs(res) > RESIDUAL_TOL * np.maximum(1.0, np.abs(t))
            bad = ~((xn >= a) & (xn <= b)) | (small & far) | (step > 0.5 * last_step)
            if np.any(bad):
                xn = np.where(bad, 0.5 * (a + b), xn)
            # converged: a Newton step this small (quadratic: the new point is far closer still),
            # a residual at the rounding level of the target (nothing left to gain: next to a fold,
            # where the slope vanishes, this is as close as float64 can pin the root), or a bracket
            # narrower than the tolerance
            at_rounding = np.abs(res) <= (RESIDUAL_ULPS * EPS) * np.abs(t)
            done = (small & ~bad) | at_rounding | (b - a <= tol)
            xn = np.where(at_rounding, x, xn)
            last_step = np.abs(xn - x)
            x = xn
            if np.any(done):
                out[idx[done]] = x[done]
                converged[idx[done]] = True
                keep = ~done
                idx, x, a, b, t = idx[keep], x[keep], a[keep], b[keep], t[keep]
                last_step = last_step[keep]
    return out, converged


# -- compiled kernels for the radial maps of the models ------------------------------------------
#: the radial maps the compiled solver inverts (``radial_value`` in ``src/native/lens_solve.h``):
#: the division model's r_u(r_d) and its reciprocal form past a pole, the Brown polynomial, the tan-fold
#: fisheye's angle, OpenCV's rational radial map and OCamCalib's angle condition
DIVISION, DIVISION_RECIPROCAL, BROWN, TAN_FISHEYE, RATIONAL, OCAM = range(6)


def inverse_table(f: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]], hi: float, n: int = 1024,
                  sqrt_map: bool = False, cap: float = np.inf) -> tuple[np.ndarray, float]:
    """Starting guesses for the compiled solvers: the inverse of an increasing ``f`` on ``[0, hi]``,
    sampled at ``n + 1`` uniform steps of ``f`` (or of ``sqrt(f)``), up to ``min(f(hi), cap)``.

    Returns ``(table, step)``: ``table[j]`` ~ the ``x`` with ``g(f(x)) = j * step``.
    """
    x = np.linspace(0.0, hi, 16 * n + 1)[:-1]
    with np.errstate(all="ignore"):
        y = f(x)[0]
    keep = np.isfinite(y) & (y <= cap)
    keep &= np.concatenate([[True], np.diff(y) > 0])  # strictly increasing samples only
    x, y = x[keep], y[keep]
    g = np.sqrt(np.maximum(y, 0.0)) if sqrt_map else y
    step = float(g[-1] / n) if g[-1] > 0 else 1.0
    table = np.interp(np.arange(n + 1) * step, g, x)
    return np.ascontiguousarray(table, dtype=FLOAT), step


def kernel_settings() -> tuple[float, float, float, int]:
    """The solver settings in the order the compiled kernels take them."""
    return TOL, RESIDUAL_TOL, RESIDUAL_ULPS * EPS, MAX_ITER
