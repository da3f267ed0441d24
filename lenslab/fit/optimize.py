"""A thin, deterministic driver around nlopt for every fit in lenslab.

``minimize(fun, start, lower, upper)`` minimises a scalar function of a few bounded parameters:

- the search runs in the unit box (each parameter mapped linearly from ``[lower, upper]`` to
  ``[0, 1]``) so that one tolerance and one initial step suit parameters of any unit;
- ``method`` picks the local algorithm: ``bobyqa`` (quadratic models with bounds, the default for
  smooth least-squares problems), ``sbplx`` (subplex, for noisy or kinked objectives) or ``cobyla``
  (the one that takes inequality constraints ``c(x) <= 0``);
- ``global_start="direct-l"`` (deterministic DIRECT-L) or ``"mlsl"`` (MLSL with a low-discrepancy
  sequence) first explores the whole box, for multimodal problems; the local method then polishes
  the best point it found;
- it stops on tolerances (``xtol``: parameter change, ``ftol``: objective change, ``stopval``:
  objective small enough), never on a fixed count; ``maxeval`` is only a generous safety cap;
- nlopt's random seed is fixed, so the same problem gives the same answer every run;
- nlopt's failures (round-off limited, forced stop, invalid arguments, failure) and an exhausted
  evaluation cap become :class:`~lenslab.errors.FitError` whose ``best`` holds the best point found.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, Sequence

import nlopt
import numpy as np

from lenslab.errors import FitError

LOCAL_METHODS = {"bobyqa": nlopt.LN_BOBYQA, "sbplx": nlopt.LN_SBPLX, "cobyla": nlopt.LN_COBYLA}
GLOBAL_METHODS = {"direct-l": nlopt.GN_DIRECT_L, "mlsl": nlopt.G_MLSL_LDS}
METHOD_NAMES = {"bobyqa": "BOBYQA", "sbplx": "Sbplx", "cobyla": "COBYLA", "direct-l": "DIRECT-L", "mlsl": "MLSL-LDS"}

RESULT_TEXT = {
    nlopt.SUCCESS: "converged",
    nlopt.STOPVAL_REACHED: "objective reached the stop value",
    nlopt.FTOL_REACHED: "objective change below tolerance",
    nlopt.XTOL_REACHED: "parameter change below tolerance",
    nlopt.MAXEVAL_REACHED: "evaluation cap reached",
    nlopt.MAXTIME_REACHED: "time limit reached",
}

NONFINITE_VALUE = 1e20  # what the optimiser sees when the objective is NaN or infinite
SEED = 20240611  # nlopt's random seed (used by MLSL and by randomised variants): fixed, for repeatable fits


@dataclass
class Stage:
    """One nlopt run: algorithm, evaluations, best value, why it stopped."""

    algorithm: str
    evaluations: int
    value: float
    status: str

    def describe(self) -> str:
        return f"{self.algorithm}: {self.evaluations} evaluations, best {self.value:.6g} ({self.status})"


@dataclass
class OptimizeResult:
    """The best point found, its value and the record of what the optimiser did."""

    x: np.ndarray
    value: float
    evaluations: int
    names: tuple[str, ...]
    stages: list[Stage] = field(default_factory=list)
    nonfinite: int = 0  # evaluations that returned NaN/inf (seen by nlopt as a large penalty)
    converged: bool = True

    def params(self) -> dict[str, float]:
        return {n: float(v) for n, v in zip(self.names, self.x)}

    def describe(self) -> str:
        lines = [s.describe() for s in self.stages]
        if self.nonfinite:
            lines.append(f"{self.nonfinite} evaluation(s) were not finite and counted as {NONFINITE_VALUE:g}")
        return "; ".join(lines)


class _Objective:
    """Wraps a user function of real parameters as an nlopt objective over the unit box."""

    def __init__(self, fun: Callable[[np.ndarray], float], lower: np.ndarray, span: np.ndarray,
                 constraints: Sequence[Callable[[np.ndarray], float]] = (), ctol: float = 0.0):
        self.fun, self.lower, self.span = fun, lower, span
        self.constraints, self.ctol = tuple(constraints), ctol
        self.best_t: np.ndarray | None = None
        self.best_f = math.inf
        self.evaluations = 0
        self.nonfinite = 0

    def to_x(self, t) -> np.ndarray:
        return self.lower + np.clip(np.asarray(t, dtype=np.float64), 0.0, 1.0) * self.span

    def __call__(self, t, grad) -> float:
        self.evaluations += 1
        f = float(self.fun(self.to_x(t)))
        if not math.isfinite(f):
            self.nonfinite += 1
            f = NONFINITE_VALUE
        if f < self.best_f or self.best_t is None:
            # with constraints, only a feasible point may become the best one
            x = self.to_x(t)
            if all(c(x) <= self.ctol for c in self.constraints):
                self.best_f, self.best_t = f, np.array(t, dtype=np.float64)
        return f


def _check_inputs(start, lower, upper, names) -> tuple[np.ndarray, np.ndarray, np.ndarray, tuple[str, ...]]:
    x0 = np.atleast_1d(np.asarray(start, dtype=np.float64))
    lo = np.atleast_1d(np.asarray(lower, dtype=np.float64))
    hi = np.atleast_1d(np.asarray(upper, dtype=np.float64))
    n = x0.size
    names = tuple(names) if names is not None else tuple(f"x{i}" for i in range(n))
    if lo.shape != (n,) or hi.shape != (n,) or len(names) != n:
        raise FitError(f"fit set-up: start, bounds and names must all have {n} entries")
    for i, name in enumerate(names):
        if not (np.isfinite(lo[i]) and np.isfinite(hi[i]) and lo[i] < hi[i]):
            raise FitError(f"parameter {name}: bounds [{lo[i]:g}, {hi[i]:g}] are not a finite, non-empty "
                           "interval; give finite bounds with lower < upper")
        if not (np.isfinite(x0[i]) and lo[i] <= x0[i] <= hi[i]):
            raise FitError(f"parameter {name}: start value {x0[i]:g} is outside its bounds "
                           f"[{lo[i]:g}, {hi[i]:g}]; start inside them or widen them")
    return x0, lo, hi, names


def _failure_text(exc: BaseException, opt) -> str:
    if isinstance(exc, nlopt.RoundoffLimited):
        return ("round-off errors stopped progress (the objective is flat or noisy at this scale); "
                "the best point may still be usable: check its residual, or try method=sbplx")
    if isinstance(exc, nlopt.ForcedStop):
        return "the fit was stopped before it converged"
    if isinstance(exc, MemoryError):
        return "nlopt ran out of memory"
    msg = ""
    try:
        msg = opt.get_errmsg() or ""
    except Exception:  # pragma: no cover - older bindings
        pass
    if "invalid" in type(exc).__name__.lower() or isinstance(exc, ValueError):
        return f"nlopt refused its arguments ({msg or exc}); check the bounds and the start values"
    return f"nlopt failed ({msg or exc or type(exc).__name__})"


def _run(opt, obj: _Objective, t0: np.ndarray, label: str, stages: list[Stage]) -> tuple[np.ndarray, int]:
    """Run one nlopt optimisation; return (best t, nlopt result code). Failures raise FitError later."""
    before = obj.evaluations
    nlopt.srand(SEED)
    try:
        t = np.asarray(opt.optimize(t0.tolist()), dtype=np.float64)
        code = opt.last_optimize_result()
    except (nlopt.RoundoffLimited, nlopt.ForcedStop, MemoryError, ValueError, RuntimeError) as exc:
        stages.append(Stage(label, obj.evaluations - before, obj.best_f, "failed"))
        raise _NloptFailure(_failure_text(exc, opt)) from exc
    except Exception as exc:
        if type(exc).__module__.startswith("nlopt"):
            stages.append(Stage(label, obj.evaluations - before, obj.best_f, "failed"))
            raise _NloptFailure(_failure_text(exc, opt)) from exc
        raise  # an error in the objective itself: let it through unchanged
    stages.append(Stage(label, obj.evaluations - before, obj.best_f, RESULT_TEXT.get(code, f"result {code}")))
    # nlopt returns its own optimum; the wrapper's record is the same point or a better one
    if obj.best_t is not None:
        t = obj.best_t
    return t, code


class _NloptFailure(Exception):
    pass


def _local(method: str, n: int, obj: _Objective, t0: np.ndarray, *, xtol_rel, xtol_abs, ftol_rel, ftol_abs,
           stopval, maxeval, step, constraints, ctol, stages) -> tuple[np.ndarray, int]:
    algorithm = LOCAL_METHODS[method]
    opt = nlopt.opt(algorithm, n)
    opt.set_lower_bounds([0.0] * n)
    opt.set_upper_bounds([1.0] * n)
    opt.set_min_objective(obj)
    opt.set_xtol_rel(xtol_rel)
    opt.set_xtol_abs([xtol_abs] * n)
    opt.set_ftol_rel(ftol_rel)
    opt.set_ftol_abs(ftol_abs)
    if stopval is not None:
        opt.set_stopval(stopval)
    opt.set_maxeval(int(maxeval))
    # initial step: a fraction of the box, shrunk near a bound so the first simplex/model fits inside
    room = np.maximum(np.minimum(t0, 1.0 - t0), 0.0)
    opt.set_initial_step(np.maximum(np.minimum(step, np.where(room > 1e-6, room, step)), 1e-6).tolist())
    for c in constraints:
        opt.add_inequality_constraint(lambda t, grad, c=c: float(c(obj.to_x(t))), ctol)
    return _run(opt, obj, t0, METHOD_NAMES[method], stages)


def minimize(
    fun: Callable[[np.ndarray], float],
    start: Sequence[float],
    lower: Sequence[float],
    upper: Sequence[float],
    *,
    names: Sequence[str] | None = None,
    method: str = "bobyqa",
    global_start: str | None = None,
    global_evals: int | None = None,
    constraints: Sequence[Callable[[np.ndarray], float]] = (),
    constraint_tol: float = 0.0,
    xtol_rel: float = 1e-10,
    xtol_abs: float = 1e-12,
    ftol_rel: float = 1e-15,
    ftol_abs: float = 0.0,
    stopval: float | None = None,
    maxeval: int | None = None,
    initial_step: float = 0.05,
) -> OptimizeResult:
    """Minimise ``fun(x)`` over the box ``lower <= x <= upper`` starting from ``start``.

    ``xtol_abs`` and ``initial_step`` are fractions of each parameter's range. ``constraints`` are
    functions ``c(x) <= 0`` (COBYLA only). ``maxeval`` defaults to ``2000 * (n + 1)``, far above what a
    converging fit uses. Returns an :class:`OptimizeResult`; raises :class:`FitError` (with ``best``) if
    nlopt fails or the cap is reached before the tolerances are met.
    """
    x0, lo, hi, names = _check_inputs(start, lower, upper, names)
    n = x0.size
    if n == 0:  # every parameter fixed: evaluate the one point there is
        value = float(fun(x0))
        return OptimizeResult(x0, value, 1, names, [Stage("no free parameter", 1, value, "evaluated once")])
    method = method.lower()
    if method not in LOCAL_METHODS:
        raise FitError(f"unknown local method {method!r}; choose one of {', '.join(LOCAL_METHODS)}")
    if constraints and method != "cobyla":
        raise FitError("constraints need method='cobyla' (the nlopt method that takes them)")
    if method == "bobyqa" and n == 1:
        method = "sbplx"  # BOBYQA's quadratic model needs at least two variables
    if global_start is not None and global_start.lower() not in GLOBAL_METHODS:
        raise FitError(f"unknown global method {global_start!r}; choose one of {', '.join(GLOBAL_METHODS)}")
    maxeval = int(maxeval or 2000 * (n + 1))
    span = hi - lo
    obj = _Objective(fun, lo, span, constraints, constraint_tol)
    stages: list[Stage] = []
    t0 = (x0 - lo) / span
    local_kw = dict(xtol_rel=xtol_rel, xtol_abs=xtol_abs, ftol_rel=ftol_rel, ftol_abs=ftol_abs, stopval=stopval,
                    step=initial_step, constraints=constraints, ctol=constraint_tol, stages=stages)

    def result(t, converged: bool) -> OptimizeResult:
        t = obj.best_t if obj.best_t is not None else t
        return OptimizeResult(obj.to_x(t), float(obj.best_f), obj.evaluations, names, stages, obj.nonfinite, converged)

    try:
        if global_start is not None:
            g = global_start.lower()
            budget = int(global_evals or max(200, 150 * n))
            gopt = nlopt.opt(GLOBAL_METHODS[g], n)
            gopt.set_lower_bounds([0.0] * n)
            gopt.set_upper_bounds([1.0] * n)
            gopt.set_min_objective(obj)
            gopt.set_maxeval(budget)
            if stopval is not None:
                gopt.set_stopval(stopval)
            if g == "mlsl":
                sub = nlopt.opt(nlopt.LN_BOBYQA if n > 1 else nlopt.LN_SBPLX, n)
                sub.set_xtol_rel(1e-6)
                sub.set_ftol_rel(1e-9)
                gopt.set_local_optimizer(sub)
            obj(t0, None)  # the given start competes with the global search
            t0, _ = _run(gopt, obj, t0, METHOD_NAMES[g] + " (global start)", stages)
        if stopval is not None and obj.best_f <= stopval:
            return result(t0, True)
        t, code = _local(method, n, obj, t0, maxeval=maxeval, **local_kw)
    except _NloptFailure as exc:
        best = result(t0, False)
        raise FitError(f"the optimiser failed: {exc}; best point found: {_fmt(best)}", best=best) from None
    res = result(t, code != nlopt.MAXEVAL_REACHED and code != nlopt.MAXTIME_REACHED)
    if not res.converged:
        raise FitError(f"the optimiser reached its safety cap of {maxeval} evaluations before converging; "
                       f"best point found: {_fmt(res)}; the problem may be ill-posed: fix a parameter or "
                       "narrow the bounds", best=res)
    return res


def _fmt(res: OptimizeResult) -> str:
    return ", ".join(f"{k}={v:.10g}" for k, v in res.params().items()) + f" (objective {res.value:.6g})"
