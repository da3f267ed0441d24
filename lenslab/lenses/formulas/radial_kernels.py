"""Compiled (numba) twin of :meth:`lenslab.lenses.formulas.radial.Radial.scale`: the radial polynomial
``P(r)`` in rising powers, by Horner's rule, one radius at a time (inlined into the lensfun kernel).
Imported on first use."""

from __future__ import annotations

import numba


@numba.njit(inline="always", cache=True, error_model="numpy")
def poly_scale(coeffs, r):
    """``P(r) = sum(coeffs[i] r^i)`` (``coeffs`` a float64 array in rising powers)."""
    p = 0.0
    for j in range(coeffs.shape[0] - 1, -1, -1):
        p = p * r + coeffs[j]
    return p
