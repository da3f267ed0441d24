"""Compiled (numba) twins of :mod:`lenslab.lenses.formulas.lonlat`, one direction at a time.

The same operations in the same order as the NumPy functions (the equirect kernel returns the very
same pixels as the NumPy map); inlined into the equirect and lensfun kernels. Imported on first use.
"""

from __future__ import annotations

import math

import numba

from lenslab.lenses.formulas.kinds import CYLINDRICAL, EQUAL_AREA_CYLINDRICAL, EQUIRECTANGULAR

JIT = dict(cache=True, error_model="numpy")


@numba.njit(inline="always", **JIT)
def dir_to_lon_height(kind, dx, dy, dz):
    """Unit direction -> ``(longitude, height, ok)`` on the cylinder ``kind`` (``ok`` False at the poles
    of the central cylinder and of Mercator, which lie at infinity)."""
    phi = math.atan2(dx, dz)
    c = math.hypot(dx, dz)
    if kind == EQUIRECTANGULAR:
        return phi, math.atan2(dy, c), True
    if kind == EQUAL_AREA_CYLINDRICAL:
        return phi, dy, True
    if not c > 0.0:
        return phi, 0.0, False
    if kind == CYLINDRICAL:
        return phi, dy / c, True
    return phi, math.asinh(dy / c), True  # MERCATOR
