"""Compiled (numba) twins of :mod:`lenslab.lenses.formulas.azimuthal`, one direction or point at a time.

The same formulas as the NumPy functions (the tests hold them to each other), inlined into the fused
kernels of the lensfun profiles and the calibrated models. Imported on first use.
"""

from __future__ import annotations

import math

import numba

from lenslab.lenses.formulas.kinds import EQUIDISTANT, EQUISOLID, ORTHOGRAPHIC, STEREOGRAPHIC, THOBY_K1, THOBY_K2

JIT = dict(cache=True, error_model="numpy")


@numba.njit(inline="always", **JIT)
def dir_to_plane(kind, dx, dy, dz):
    """Unit direction -> ``(x, y, ok)`` on the plane at unit focal length (``ok`` False where the mapping
    does not see it: orthographic behind the camera, Thoby beyond its 126 degrees, the back pole of
    the mappings whose rim is a whole circle there)."""
    rho = math.sqrt(dx * dx + dy * dy)
    if kind == EQUIDISTANT:
        if not rho > 0.0:
            return 0.0, 0.0, dz > 0.0
        k = math.atan2(rho, dz) / rho
    elif kind == EQUISOLID:
        if dz >= 0.0:
            k = 2.0 / math.sqrt(2.0 * (1.0 + dz))
        elif rho > 0.0:
            k = math.sqrt(2.0 * (1.0 - dz)) / rho
        else:
            return 0.0, 0.0, False
    elif kind == STEREOGRAPHIC:
        if dz >= 0.0:
            k = 2.0 / (1.0 + dz)
        elif rho > 0.0:
            k = 2.0 * (1.0 - dz) / (rho * rho)
        else:
            return 0.0, 0.0, False
    elif kind == ORTHOGRAPHIC:
        if not dz >= 0.0:
            return 0.0, 0.0, False
        k = 1.0
    else:  # THOBY
        theta = math.atan2(rho, dz)
        if not THOBY_K2 * theta <= 0.5 * math.pi:
            return 0.0, 0.0, False
        k = THOBY_K1 * math.sin(THOBY_K2 * theta) / rho if rho > 0.0 else THOBY_K1 * THOBY_K2
    return dx * k, dy * k, True


@numba.njit(inline="always", **JIT)
def plane_to_dir(kind, x, y):
    """Plane point (unit focal length) -> unit direction ``(dx, dy, dz, ok)``."""
    s2 = x * x + y * y
    if kind == EQUIDISTANT:
        s = math.sqrt(s2)
        if not s <= math.pi:
            return 0.0, 0.0, 0.0, False
        k = math.sin(s) / s if s > 0.0 else 1.0
        return x * k, y * k, math.cos(s), True
    if kind == EQUISOLID:
        q = 0.25 * s2
        if not q <= 1.0:
            return 0.0, 0.0, 0.0, False
        k = math.sqrt(1.0 - q)
        return x * k, y * k, 1.0 - 2.0 * q, True
    if kind == STEREOGRAPHIC:
        q2 = 0.25 * s2
        k = 1.0 / (1.0 + q2)
        return x * k, y * k, k * (1.0 - q2), True
    if kind == ORTHOGRAPHIC:
        if not s2 <= 1.0:
            return 0.0, 0.0, 0.0, False
        return x, y, math.sqrt(1.0 - s2), True
    s = math.sqrt(s2)  # THOBY
    if not s <= THOBY_K1:
        return 0.0, 0.0, 0.0, False
    theta = math.asin(s / THOBY_K1) / THOBY_K2
    k = math.sin(theta) / s if s > 0.0 else 1.0 / (THOBY_K1 * THOBY_K2)
    return x * k, y * k, math.cos(theta), True
