"""The projections of the calibrated camera models on bare float64 arrays (NumPy): rays in OpenCV's camera
frame (``X`` right, ``Y`` down, ``Z`` forward) <-> points of the plane at unit focal length, before
distortion. The compiled twins the models run are in ``src/native/lens_formulas.h``;
these are their reference (the tests hold the two to each other, and both to OpenCV and the papers).

``kind`` (:mod:`lenslab.lenses.formulas.kinds`) and ``q``::

    RECTILINEAR    (X, Y) / Z                                      OpenCV's pinhole
    FOV            (X, Y) / Z scaled to r_d = atan(2 r_u tan(w/2)) / w,  q = (w, 2 tan(w/2))   Devernay-Faugeras
    EQUIDISTANT    theta (X, Y) / rho                              cv2.fisheye, Kannala-Brandt
    UNIFIED        (X, Y) / (Z + xi),  q = (xi, w)                 Mei (cv2.omnidir)
    DOUBLE_SPHERE  (X, Y) / (alpha d2 + (1 - alpha)(xi d1 + Z)),  q = (xi, alpha, w2)     Usenko et al. 2018
    EUCM           (X, Y) / (alpha d + (1 - alpha) Z),  d = sqrt(beta (X^2 + Y^2) + Z^2),  q = (alpha, beta, w)

``w``, ``w2`` bound each model's valid region (the papers' ``z > -w ...`` conditions).

>>> import numpy as np
>>> mx, my, ok = project(UNIFIED, np.array([0.6]), np.array([0.0]), np.array([0.8]), (1.0, 1.0))
>>> round(float(mx[0]), 12), ok.tolist()   # 0.6 / (0.8 + 1)
(0.333333333333, [True])
"""

from __future__ import annotations

import numpy as np

from lenslab.lenses.formulas import azimuthal
from lenslab.lenses.formulas.kinds import DOUBLE_SPHERE, EQUIDISTANT, EUCM, FOV, RECTILINEAR, UNIFIED  # noqa: F401


def fov_factor(ru, omega: float, t2: float):
    """``r_d / r_u`` of the FOV model (its limits at ``r_u = 0`` and ``omega = 0``)."""
    ru = np.asarray(ru, dtype=np.float64)
    if omega == 0.0:
        return np.ones(ru.shape)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(ru > 0.0, np.arctan(ru * t2) / (omega * ru), t2 / omega)


def project(kind: int, X, Y, Z, q=()):
    """Unit rays -> ``(mx, my, ok)`` on the model's plane (zero where not ``ok``)."""
    X, Y, Z = (np.asarray(a, dtype=np.float64) for a in (X, Y, Z))
    with np.errstate(divide="ignore", invalid="ignore"):
        if kind in (RECTILINEAR, FOV):
            ok = Z > 0.0
            mx, my = X / Z, Y / Z
            if kind == FOV:
                k = fov_factor(np.sqrt(mx * mx + my * my), q[0], q[1])
                mx, my = mx * k, my * k
        elif kind == EQUIDISTANT:
            xy, _, ok = azimuthal.dir_to_plane(EQUIDISTANT, np.stack([X, Y, Z], -1))
            ok = ok & ~((X * X + Y * Y == 0) & (Z < 0))  # the back pole (rho 0 in float64) is a circle of the plane
            mx, my = xy[..., 0], xy[..., 1]
        else:
            if kind == UNIFIED:
                den = Z + q[0]
                ok = Z > -q[1]
            elif kind == DOUBLE_SPHERE:
                d1 = np.sqrt(X * X + Y * Y + Z * Z)
                zz = q[0] * d1 + Z
                den = q[1] * np.sqrt(X * X + Y * Y + zz * zz) + (1.0 - q[1]) * zz
                ok = Z > -q[2] * d1
            elif kind == EUCM:
                dd = np.sqrt(q[1] * (X * X + Y * Y) + Z * Z)
                den = q[0] * dd + (1.0 - q[0]) * Z
                ok = Z > -q[2] * dd
            else:
                raise ValueError(f"not a calibrated projection code: {kind}")
            ok = ok & (den > 0.0)
            mx, my = X / den, Y / den
    ok = ok & np.isfinite(mx) & np.isfinite(my)
    return np.where(ok, mx, 0.0), np.where(ok, my, 0.0), ok


def unproject(kind: int, mx, my, q=()):
    """Plane points -> unit rays ``(X, Y, Z, ok)`` of the model (zero where not ``ok``)."""
    mx, my = np.asarray(mx, dtype=np.float64), np.asarray(my, dtype=np.float64)
    r2 = mx * mx + my * my
    one = np.ones(r2.shape)
    ok = np.ones(r2.shape, dtype=bool)
    with np.errstate(divide="ignore", invalid="ignore"):
        if kind == RECTILINEAR:
            X, Y, Z = mx, my, one
        elif kind == FOV:
            rd = np.sqrt(r2)
            ok = rd * q[0] < 0.5 * np.pi
            if q[0] == 0.0:
                k = one
            else:
                k = np.where(rd > 0.0, np.tan(rd * q[0]) / (rd * q[1]), q[0] / q[1])
            X, Y, Z = mx * k, my * k, one
        elif kind == EQUIDISTANT:
            ok = r2 < np.pi * np.pi  # the rim circle is the back pole
            d, _ = azimuthal.plane_to_dir(EQUIDISTANT, mx, my)
            X, Y, Z = d[..., 0], d[..., 1], d[..., 2]
        elif kind == UNIFIED:
            xi = q[0]
            disc = 1.0 + (1.0 - xi * xi) * r2
            if xi > 1.0:
                ok = disc > 0.0
            k = (xi + np.sqrt(np.maximum(disc, 0.0))) / (r2 + 1.0)
            X, Y, Z = k * mx, k * my, k - xi
        elif kind == DOUBLE_SPHERE:
            xi, al = q[0], q[1]
            qq = 1.0 - (2.0 * al - 1.0) * r2
            if al > 0.5:
                ok = qq >= 0.0
            mz = (1.0 - al * al * r2) / (al * np.sqrt(np.maximum(qq, 0.0)) + 1.0 - al)
            k = (mz * xi + np.sqrt(np.maximum(mz * mz + (1.0 - xi * xi) * r2, 0.0))) / (mz * mz + r2)
            X, Y, Z = k * mx, k * my, k * mz - xi
            ok = ok & (Z > -q[2])  # the paper's region z > -w2 |x| (unit ray)
        elif kind == EUCM:
            al, be = q[0], q[1]
            qq = 1.0 - (2.0 * al - 1.0) * be * r2
            if al > 0.5:
                ok = qq >= 0.0
            X, Y, Z = mx, my, (1.0 - be * al * al * r2) / (al * np.sqrt(np.maximum(qq, 0.0)) + 1.0 - al)
        else:
            raise ValueError(f"not a calibrated projection code: {kind}")
        n = np.sqrt(X * X + Y * Y + Z * Z)
        ok = ok & (n > 0.0) & (n < np.inf)
        X, Y, Z = X / n, Y / n, Z / n
        if kind == EUCM:
            ok = ok & (Z > -q[2] * np.sqrt(q[1] * (X * X + Y * Y) + Z * Z))
    return tuple(np.where(ok, a, 0.0) for a in (X, Y, Z)) + (ok,)
