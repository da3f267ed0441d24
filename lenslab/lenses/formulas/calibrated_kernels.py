"""Compiled (numba) projections of the calibrated camera models, one ray or point at a time: the twins
of :mod:`lenslab.lenses.formulas.calibrated` (the tests hold the two to each other), inlined into the
calibrated models' fused kernels (:mod:`lenslab.lenses.calibrated.kernels`). Imported on first use.

Rays and plane points are in OpenCV's camera frame (``X`` right, ``Y`` down, ``Z`` forward), the plane at
unit focal length before distortion; ``q`` holds each model's parameters (see ``project_one``).
"""

from __future__ import annotations

import math

import numba

from lenslab.lenses.formulas import azimuthal_kernels as az
from lenslab.lenses.formulas.kinds import DOUBLE_SPHERE, EQUIDISTANT, EUCM, FOV, RECTILINEAR, UNIFIED

JIT = dict(cache=True, error_model="numpy")
PINHOLE = RECTILINEAR


@numba.njit(inline="always", **JIT)
def fov_factor(ru, omega, t2):
    """``r_d / r_u`` of the FOV model, ``atan(r_u t2) / (omega r_u)`` with ``t2 = 2 tan(omega/2)`` (its
    limits at ``r_u = 0`` and ``omega = 0``)."""
    if omega == 0.0:
        return 1.0
    if ru > 0.0:
        return math.atan(ru * t2) / (omega * ru)
    return t2 / omega


@numba.njit(inline="always", **JIT)
def project_one(kind, X, Y, Z, q):
    """A unit ray -> ``(mx, my, ok)`` on the model's plane: PINHOLE ``X/Z``; FOV ``X/Z`` scaled to
    ``r_d = atan(2 r_u tan(omega/2)) / omega``, ``q = (omega, 2 tan(omega/2))``; EQUIDISTANT
    ``theta (X, Y)/rho``; UNIFIED (Mei) ``X/(Z + xi)``, ``q = (xi, w)``; DOUBLE_SPHERE ``q = (xi, alpha, w2)``;
    EUCM ``q = (alpha, beta, w)``."""
    if kind == PINHOLE or kind == FOV:
        if not Z > 0.0:
            return 0.0, 0.0, False
        mx = X / Z
        my = Y / Z
        if kind == FOV:  # Devernay-Faugeras: r_d = atan(2 r_u tan(omega/2)) / omega; q = (omega, 2 tan(omega/2))
            ru = math.sqrt(mx * mx + my * my)
            k = fov_factor(ru, q[0], q[1])
            mx *= k
            my *= k
    elif kind == EQUIDISTANT:  # the back pole (a whole circle of the plane) is not seen
        mx, my, seen = az.dir_to_plane(EQUIDISTANT, X, Y, Z)
        if not seen:
            return 0.0, 0.0, False
    elif kind == UNIFIED:
        den = Z + q[0]
        if not (Z > -q[1] and den > 0.0):
            return 0.0, 0.0, False
        mx = X / den
        my = Y / den
    elif kind == DOUBLE_SPHERE:
        xi = q[0]
        al = q[1]
        d1 = math.sqrt(X * X + Y * Y + Z * Z)
        zz = xi * d1 + Z
        d2 = math.sqrt(X * X + Y * Y + zz * zz)
        den = al * d2 + (1.0 - al) * zz
        if not (Z > -q[2] * d1 and den > 0.0):
            return 0.0, 0.0, False
        mx = X / den
        my = Y / den
    else:  # EUCM
        al = q[0]
        dd = math.sqrt(q[1] * (X * X + Y * Y) + Z * Z)
        den = al * dd + (1.0 - al) * Z
        if not (Z > -q[2] * dd and den > 0.0):
            return 0.0, 0.0, False
        mx = X / den
        my = Y / den
    return mx, my, True


@numba.njit(inline="always", **JIT)
def unproject_one(kind, mx, my, q):
    """A plane point -> the unit ray ``(X, Y, Z, ok)`` of the model (``kind`` and ``q`` as for
    :func:`project_one`): each model's closed-form inverse."""
    r2 = mx * mx + my * my
    if kind == PINHOLE:
        X, Y, Z = mx, my, 1.0
    elif kind == FOV:  # r_u = tan(r_d omega) / (2 tan(omega/2)), valid for r_d omega < pi/2
        rd = math.sqrt(r2)
        if not rd * q[0] < 0.5 * math.pi:
            return 0.0, 0.0, 0.0, False
        if q[0] == 0.0:
            k = 1.0
        elif rd > 0.0:
            k = math.tan(rd * q[0]) / (rd * q[1])
        else:
            k = q[0] / q[1]
        X, Y, Z = mx * k, my * k, 1.0
    elif kind == EQUIDISTANT:
        if not r2 < math.pi * math.pi:  # the rim circle is the back pole: kept out, as ever
            return 0.0, 0.0, 0.0, False
        X, Y, Z, _ = az.plane_to_dir(EQUIDISTANT, mx, my)
    elif kind == UNIFIED:
        xi = q[0]
        disc = 1.0 + (1.0 - xi * xi) * r2
        if xi > 1.0 and not disc > 0.0:
            return 0.0, 0.0, 0.0, False
        k = (xi + math.sqrt(max(disc, 0.0))) / (r2 + 1.0)
        X, Y, Z = k * mx, k * my, k - xi
    elif kind == DOUBLE_SPHERE:
        xi = q[0]
        al = q[1]
        qq = 1.0 - (2.0 * al - 1.0) * r2
        if al > 0.5 and qq < 0.0:
            return 0.0, 0.0, 0.0, False
        mz = (1.0 - al * al * r2) / (al * math.sqrt(max(qq, 0.0)) + 1.0 - al)
        k = (mz * xi + math.sqrt(max(mz * mz + (1.0 - xi * xi) * r2, 0.0))) / (mz * mz + r2)
        X, Y, Z = k * mx, k * my, k * mz - xi
        if not Z > -q[2]:  # the paper's region z > -w2 |x| (unit ray)
            return 0.0, 0.0, 0.0, False
    else:  # EUCM
        al = q[0]
        be = q[1]
        qq = 1.0 - (2.0 * al - 1.0) * be * r2
        if al > 0.5 and qq < 0.0:
            return 0.0, 0.0, 0.0, False
        X, Y, Z = mx, my, (1.0 - be * al * al * r2) / (al * math.sqrt(max(qq, 0.0)) + 1.0 - al)
    n = math.sqrt(X * X + Y * Y + Z * Z)
    if not (n > 0.0 and n < math.inf):
        return 0.0, 0.0, 0.0, False
    X /= n
    Y /= n
    Z /= n
    if kind == EUCM and not Z > -q[2] * math.sqrt(q[1] * (X * X + Y * Y) + Z * Z):
        return 0.0, 0.0, 0.0, False
    return X, Y, Z, True
