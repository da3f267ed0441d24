"""The nlopt driver: convergence on tolerances, global starts, constraints, determinism, failures."""

from __future__ import annotations

import math

import nlopt
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lenslab.errors import FitError
from lenslab.fit.optimize import minimize


def rosenbrock(x):
    return (1 - x[0]) ** 2 + 100 * (x[1] - x[0] ** 2) ** 2


@pytest.mark.parametrize("method", ["bobyqa", "sbplx"])
def test_rosenbrock_minimum_is_found(method):
    res = minimize(rosenbrock, [-1.2, 1.0], [-2, -2], [2, 3], names=["a", "b"], method=method)
    # the minimum is (1, 1); xtol 1e-10 of the range and a smooth valley: 1e-6 leaves room for Sbplx
    assert res.x == pytest.approx([1.0, 1.0], abs=1e-6)
    assert res.converged
    assert res.params() == pytest.approx({"a": 1.0, "b": 1.0}, abs=1e-6)
    assert res.stages and res.evaluations >= res.stages[-1].evaluations


@settings(max_examples=25, deadline=None)
@given(st.lists(st.floats(-5, 5), min_size=1, max_size=4), st.floats(0.1, 0.9))
def test_quadratic_minimum_recovered_from_any_start(centre, frac):
    """A bounded quadratic's minimum is recovered to the tolerance wherever the search starts."""
    c = np.asarray(centre)
    lo, hi = c - 3.0, c + 7.0
    start = lo + frac * (hi - lo)
    res = minimize(lambda x: float(np.sum((x - c) ** 2)), start, lo, hi)
    # xtol_abs is 1e-12 of a range of 10: the answer is far inside 1e-7
    assert np.allclose(res.x, c, atol=1e-7)


def test_same_answer_twice():
    def bumpy(x):
        return math.sin(3 * x[0]) * math.cos(2 * x[1]) + 0.1 * (x[0] ** 2 + x[1] ** 2)

    for g in (None, "direct-l", "mlsl"):
        a = minimize(bumpy, [1.0, 1.0], [-3, -3], [3, 3], global_start=g)
        b = minimize(bumpy, [1.0, 1.0], [-3, -3], [3, 3], global_start=g)
        assert np.array_equal(a.x, b.x) and a.value == b.value and a.evaluations == b.evaluations


def test_global_start_escapes_a_local_minimum():
    # two basins: a shallow one at x = -2 (value 0.5) and the deep one at x = 3 (value 0)
    def f(x):
        return min((x[0] + 2) ** 2 + 0.5, (x[0] - 3) ** 2) + 0.0 * x[1]

    local = minimize(f, [-1.5, 0.0], [-5, -1], [5, 1])
    assert local.x[0] == pytest.approx(-2, abs=1e-6)  # a local method stays in its basin
    for g in ("direct-l", "mlsl"):
        res = minimize(f, [-1.5, 0.0], [-5, -1], [5, 1], global_start=g)
        assert res.x[0] == pytest.approx(3, abs=1e-6), g
        assert any("global" in s.algorithm for s in res.stages)


def test_cobyla_respects_an_inequality_constraint():
    # maximise x + y on the unit disc: (1/sqrt2, 1/sqrt2)
    res = minimize(lambda x: -(x[0] + x[1]), [0.0, 0.0], [-2, -2], [2, 2], method="cobyla",
                   constraints=[lambda x: x[0] ** 2 + x[1] ** 2 - 1.0])
    # COBYLA's linear approximations converge on the circle to about the xtol: 1e-6 is ample
    assert res.x == pytest.approx([2 ** -0.5, 2 ** -0.5], abs=1e-6)
    assert res.x[0] ** 2 + res.x[1] ** 2 <= 1.0 + 1e-9


def test_nothing_free_evaluates_once():
    res = minimize(lambda x: 42.0, [], [], [])
    assert res.value == 42.0 and res.evaluations == 1


@pytest.mark.parametrize("exc", [nlopt.RoundoffLimited, nlopt.ForcedStop])
def test_nlopt_failures_become_fit_errors_with_the_best_point(exc):
    values = []

    def f(x):
        if len(values) >= 15:
            raise exc()
        values.append((x[0] - 0.3) ** 2 + (x[1] + 0.2) ** 2)
        return values[-1]

    with pytest.raises(FitError) as info:
        minimize(f, [0.9, 0.9], [-1, -1], [1, 1])
    best = info.value.best
    assert best is not None and not best.converged
    # the point kept is the best one evaluated, and the message gives it
    assert best.value == min(values)
    assert (best.x[0] - 0.3) ** 2 + (best.x[1] + 0.2) ** 2 == pytest.approx(min(values), rel=1e-12)
    assert "best point found" in str(info.value) and "failed" in str(info.value)


def test_evaluation_cap_is_a_fit_error_that_keeps_the_best_point():
    with pytest.raises(FitError, match="safety cap") as info:
        minimize(rosenbrock, [-1.2, 1.0], [-2, -2], [2, 3], maxeval=20)
    assert info.value.best is not None and info.value.best.evaluations == 20


def test_non_finite_values_are_counted_not_fatal():
    res = minimize(lambda x: math.inf if x[0] < 0 else (x[0] - 0.5) ** 2 + x[1] ** 2, [0.1, 0.1], [-1, -1], [1, 1])
    assert res.x == pytest.approx([0.5, 0.0], abs=1e-6)


@pytest.mark.parametrize("lo,hi,start,msg", [
    ([1.0], [0.0], [0.5], "bounds"),
    ([0.0], [1.0], [2.0], "outside its bounds"),
    ([0.0], [math.inf], [0.5], "bounds"),
])
def test_invalid_arguments_are_explained(lo, hi, start, msg):
    with pytest.raises(FitError, match=msg):
        minimize(lambda x: 0.0, start, lo, hi, names=["k"])


def test_unknown_methods_and_misplaced_constraints_are_refused():
    with pytest.raises(FitError, match="unknown local method"):
        minimize(lambda x: 0.0, [0.5], [0], [1], method="newton")
    with pytest.raises(FitError, match="unknown global method"):
        minimize(lambda x: 0.0, [0.5], [0], [1], global_start="anneal")
    with pytest.raises(FitError, match="cobyla"):
        minimize(lambda x: 0.0, [0.5], [0], [1], constraints=[lambda x: 0.0])
