"""The lens kernels' bindings (lenslab.cxx_kernels) refuse parameters that would make a kernel index outside its
arrays or convert a float that is not a whole number in range (NaN, 1e30) to an integer: a one-line ValueError
before any point is read."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab import cxx_kernels as K

SOLVER = (1e-12, 1e-12, 4.0, 50)  # tol, res_tol, rel_ulps, max_iter


def _division(step):
    uv = np.array([[0.3, 0.4], [2.0, 1.0]])
    table = np.linspace(0.0, 1.0, 16)
    K.division_unbend(uv, -0.1, 0.0, 1.0, 1.0, False, False, table, step, *SOLVER, np.zeros((2, 2)),
                      np.zeros(2, bool))


@pytest.mark.parametrize("step", [-1.0, -1e-300, 0.0, np.nan, np.inf])
def test_a_table_step_that_is_not_a_positive_number_is_refused(step):
    """The initial guess indexes the inverse's table at t / step: a negative step is a negative index."""
    with pytest.raises(ValueError, match="step"):
        _division(step)


def test_a_positive_table_step_solves():
    _division(1.0 / 15.0)


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
