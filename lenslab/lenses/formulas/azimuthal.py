"""Azimuthal projections (the fisheye mappings) on bare float64 arrays, with unit focal length.

The angle from the axis ``theta`` and the image-plane radius ``s`` are tied by one formula per
mapping (codes from :mod:`lenslab.lenses.formulas.kinds`)::

    equidistant    s = theta
    equisolid      s = 2 sin(theta/2)
    stereographic  s = 2 tan(theta/2)
    orthographic   s = sin(theta)            (theta <= 90 deg)
    thoby          s = K1 sin(K2 theta)      (lensfun's fit, K1 = 1.47, K2 = 0.713)

A point ``(x, y)`` of the plane is the direction ``(sin(theta) x/s, sin(theta) y/s, cos(theta))``
(+z at ``s = 0``, the limit). Both ways avoid trigonometry where an identity allows it (equisolid:
``sin(theta)/s = sqrt(1 - s^2/4)``; stereographic: with ``q = s/2``, ``sin(theta)/s = 1/(1 + q^2)``;
the inverses through ``rho = hypot(dx, dy)`` and ``dz``, with the complementary form behind the camera).
The fisheye lens, the lensfun profiles and the calibrated Kannala-Brandt model all use these; the
compiled twins are in ``src/native/lens_formulas.h``.

>>> import numpy as np
>>> d, ok = plane_to_dir(EQUISOLID, np.array([np.sqrt(2.0)]), np.array([0.0]))
>>> (np.round(d, 12) + 0.0).tolist(), ok.tolist()   # s = sqrt(2) is 90 degrees from the axis
([[1.0, 0.0, 0.0]], [True])
>>> round(float(radius_of_angle(STEREOGRAPHIC, np.pi / 2)), 12)
2.0
"""

from __future__ import annotations

import numpy as np

from lenslab.lenses.formulas.kinds import (  # noqa: F401  (the codes callers pass)
    AZIMUTHAL, EQUIDISTANT, EQUISOLID, ORTHOGRAPHIC, STEREOGRAPHIC, THOBY, THOBY_K1, THOBY_K2)


def radius_of_angle(kind: int, theta):
    """``s(theta)``, the plane radius at angle ``theta`` (radians) from the axis."""
    theta = np.asarray(theta, dtype=np.float64)
    if kind == EQUIDISTANT:
        return theta.copy()
    if kind == EQUISOLID:
        return 2.0 * np.sin(0.5 * theta)
    if kind == STEREOGRAPHIC:
        return 2.0 * np.tan(0.5 * theta)
    if kind == ORTHOGRAPHIC:
        return np.sin(theta)
    if kind == THOBY:
        return THOBY_K1 * np.sin(THOBY_K2 * theta)
    raise ValueError(f"not an azimuthal projection code: {kind}")


def largest_angle(kind: int) -> float:
    """The largest angle from the axis a mapping reaches (radians): pi, but 90 degrees orthographic and
    90 / K2 degrees for Thoby."""
    return {ORTHOGRAPHIC: 0.5 * np.pi, THOBY: 0.5 * np.pi / THOBY_K2}.get(kind, np.pi)


def largest_radius(kind: int) -> float:
    """``s`` at :func:`largest_angle` (stereographic: infinite)."""
    if kind == STEREOGRAPHIC:
        return np.inf
    return float(radius_of_angle(kind, largest_angle(kind)))


def plane_to_dir(kind: int, x, y, out=None):
    """Plane points ``(x, y)`` (unit focal length) -> unit directions ``(..., 3)`` and where the
    mapping holds a ray (``s`` up to :func:`largest_radius`, with ``slack`` of it)."""
    x = np.asarray(x, dtype=np.float64)
    y = np.asarray(y, dtype=np.float64)
    s2 = x * x + y * y
    d = np.empty(x.shape + (3,), dtype=np.float64) if out is None else out
    with np.errstate(invalid="ignore", divide="ignore"):
        if kind == EQUIDISTANT:
            s = np.sqrt(s2)
            k = np.divide(np.sin(s), s, out=np.ones(s.shape), where=s > 0)  # sin(theta)/s, limit 1
            np.cos(s, out=d[..., 2])
        elif kind == EQUISOLID:  # sin(theta) = s sqrt(1 - s^2/4), cos(theta) = 1 - s^2/2
            q = 0.25 * s2
            k = np.sqrt(np.maximum(1.0 - q, 0.0))
            np.multiply(q, -2.0, out=d[..., 2])
            d[..., 2] += 1.0
            np.maximum(d[..., 2], -1.0, out=d[..., 2])  # s^2/4 a rounding past 1 at the back pole: still unit
        elif kind == STEREOGRAPHIC:  # q = s/2 = tan(theta/2): sin = 2q/(1+q^2), cos = (1-q^2)/(1+q^2)
            q2 = 0.25 * s2
            k = 1.0 / (1.0 + q2)
            np.multiply(k, 1.0 - q2, out=d[..., 2])
        elif kind == ORTHOGRAPHIC:
            k = np.ones(s2.shape)
            np.sqrt(np.maximum(1.0 - s2, 0.0), out=d[..., 2])
        elif kind == THOBY:
            s = np.sqrt(s2)
            theta = np.arcsin(np.minimum(s / THOBY_K1, 1.0)) / THOBY_K2
            k = np.divide(np.sin(theta), s, out=np.full(s.shape, 1.0 / (THOBY_K1 * THOBY_K2)), where=s > 0)
            np.cos(theta, out=d[..., 2])
        else:
            raise ValueError(f"not an azimuthal projection code: {kind}")
    np.multiply(x, k, out=d[..., 0])
    np.multiply(y, k, out=d[..., 1])
    return d, s2 <= largest_radius(kind) ** 2


def dir_to_plane(kind: int, d):
    """Unit directions ``(..., 3)`` -> plane points ``(..., 2)`` (unit focal length), their radius ``s``
    and where the mapping sees the direction. At the back pole (every azimuth at once) the point is
    ``(s, 0)``."""
    d = np.asarray(d, dtype=np.float64)
    dx, dy, dz = d[..., 0], d[..., 1], d[..., 2]
    rho2 = dx * dx + dy * dy
    rho = np.sqrt(rho2)
    ok = np.ones(rho.shape, dtype=bool)
    with np.errstate(invalid="ignore", divide="ignore"):
        if kind == EQUIDISTANT:
            s = np.arctan2(rho, dz)
            k = np.divide(s, rho, out=np.ones(s.shape), where=rho > 0)
        elif kind == EQUISOLID:  # s = 2 sin(theta/2) = 2 rho / sqrt(2 (1 + dz)) in front, sqrt(2 (1 - dz)) behind
            k = np.sqrt(2.0 * (1.0 + dz))
            np.divide(2.0, k, out=k)
            s = k * rho
            back = dz < 0
            if back.any():
                s[back] = np.sqrt(2.0 * (1.0 - dz[back]))
                k[back] = s[back] / rho[back]
        elif kind == STEREOGRAPHIC:  # s = 2 tan(theta/2) = 2 rho / (1 + dz) in front, 2 (1 - dz) / rho behind
            k = 2.0 / (1.0 + dz)
            s = k * rho
            back = dz < 0
            if back.any():
                num = 2.0 * (1.0 - dz[back])
                s[back] = num / rho[back]
                k[back] = num / rho2[back]
            ok = dz > -1.0
        elif kind == ORTHOGRAPHIC:
            k = np.ones(rho.shape)
            s = rho
            ok = dz >= 0
        elif kind == THOBY:
            theta = np.arctan2(rho, dz)
            s = THOBY_K1 * np.sin(THOBY_K2 * theta)
            k = np.divide(s, rho, out=np.full(s.shape, THOBY_K1 * THOBY_K2), where=rho > 0)
            ok = THOBY_K2 * theta <= 0.5 * np.pi
        else:
            raise ValueError(f"not an azimuthal projection code: {kind}")
    xy = np.empty(d.shape[:-1] + (2,), dtype=np.float64)
    with np.errstate(invalid="ignore"):  # 0 * inf at the stereographic back pole, replaced below
        np.multiply(dx, k, out=xy[..., 0])
        np.multiply(dy, k, out=xy[..., 1])
    pole = (rho == 0) & (dz < 0)
    if np.any(pole):
        xy[pole] = np.stack([s[pole], np.zeros(int(pole.sum()))], -1)
    return xy, s, ok
