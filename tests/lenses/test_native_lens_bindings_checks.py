"""The lens kernels' bindings (lenslab.cxx_kernels) refuse parameters that would make a kernel index outside its
arrays or convert a float that is not a whole number in range (NaN, 1e30) to an integer: a one-line ValueError
before any point is read."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab import cxx_kernels as K
from lenslab.lenses.formulas.solve import kernel_settings

SOLVER = kernel_settings()  # tol, res_tol, rel_ulps, max_iter: what the lens models pass


def _division(step):
    """The division model's solved side for (0.3, 0.4) (r_u = 0.5) and (2, 1) (beyond f_hi = 1)."""
    uv = np.array([[0.3, 0.4], [2.0, 1.0]])
    table = np.linspace(0.0, 1.0, 16)
    out, ok = np.zeros((2, 2)), np.zeros(2, bool)
    K.division_unbend(uv, -0.1, 0.0, 1.0, 1.0, False, False, table, step, *SOLVER, out, ok)
    return out, ok


@pytest.mark.parametrize("step", [-1.0, -1e-300, 0.0, np.nan, np.inf])
def test_a_table_step_that_is_not_a_positive_number_is_refused(step):
    """The initial guess indexes the inverse's table at t / step: a negative step is a negative index."""
    with pytest.raises(ValueError, match="step"):
        _division(step)


def test_a_positive_table_step_solves():
    """r_u = r_d / (1 + k1 r_d^2) solved in closed form (transcribed in float64): r_d = (1 - sqrt(1 - 4 k1 r_u^2))
    / (2 k1 r_u), along the point's direction; the point beyond f_hi is invalid and zero. 1e-12: the solver's
    tolerance (1e-13) with the scale's rounding."""
    out, ok = _division(1.0 / 15.0)
    k1, ru = -0.1, 0.5
    rd = (1.0 - np.sqrt(1.0 - 4.0 * k1 * ru * ru)) / (2.0 * k1 * ru)
    np.testing.assert_allclose(out[0], np.array([0.3, 0.4]) * (rd / ru), rtol=0, atol=1e-12)
    assert ok.tolist() == [True, False] and out[1].tolist() == [0.0, 0.0]


def _tile(kernel_id=1.0, nparams=6.0):
    """One tile's record: kernel, parameter count, reach, axis, rotation, offsets and limits, then the kernel's
    parameters (perspective: 6)."""
    return [kernel_id, nparams, -2.0, 0.0, 0.0, 1.0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0.0, 0.0, 64.0, 64.0,
            64.0, 64.0, 1.0, 1.0, 1.0, 0.0]


@pytest.mark.parametrize("params", [
    [np.nan] + _tile(), [1e30] + _tile(), [-1e30] + _tile(), [1.5] + _tile(),
    [1.0] + _tile(kernel_id=np.nan), [1.0] + _tile(kernel_id=1e30), [1.0] + _tile(kernel_id=-3.0),
    [1.0] + _tile(kernel_id=1.5),
], ids=["count-nan", "count-1e30", "count-neg", "count-half", "id-nan", "id-1e30", "id-neg", "id-half"])
def test_a_tiled_record_that_is_not_whole_numbers_is_refused(params):
    with pytest.raises(ValueError, match="tiled"):
        K.tiled_pixels(np.array([[0.0, 0.0, 1.0]]), np.array(params), np.zeros((1, 2)), np.zeros(1, bool))


def test_a_whole_tiled_record_runs():
    """The same record with whole numbers is read: a direction straight ahead lands inside the tile."""
    xy, ok = np.zeros((1, 2)), np.zeros(1, bool)
    K.tiled_pixels(np.array([[0.0, 0.0, 1.0]]), np.array([1.0] + _tile()), xy, ok)
    assert ok[0] and np.all(np.isfinite(xy))
