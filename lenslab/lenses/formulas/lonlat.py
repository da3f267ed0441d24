"""Longitude and latitude: the equirectangular and cylindrical projections on bare float64 arrays.

Longitude ``phi`` (0 forward, +z; positive toward +x) and latitude ``theta`` (positive up, +y) of a
direction ``d = (cos(theta) sin(phi), sin(theta), cos(theta) cos(phi))``; the inverse is
``phi = atan2(dx, dz)`` with ``(sin(theta), cos(theta)) = (dy, hypot(dx, dz))`` for a unit direction.
The cylinders differ only in how the image height ``y`` spaces the latitude (codes from
:mod:`lenslab.lenses.formulas.kinds`; J. P. Snyder, *Map Projections - A Working Manual*, 1987)::

    equirectangular         y = theta
    cylindrical (central)   y = tan(theta)
    equal-area (Lambert)    y = sin(theta)
    mercator                y = atanh(sin(theta)) = ln tan(pi/4 + theta/2)

Used by the equirect and cylinder models and the lensfun profiles (``equirectangular`` and
``panoramic``); the compiled twins are in ``src/native/lens_formulas.h``.

>>> import numpy as np
>>> s, c, ok = height_to_lat(MERCATOR, np.array([np.log(np.tan(np.pi / 4 + np.pi / 12))]))
>>> round(float(np.degrees(np.arctan2(s, c))[0]), 9), ok.tolist()   # y of 30 degrees -> 30 degrees
(30.0, [True])
"""

from __future__ import annotations

import numpy as np

from lenslab.lenses.formulas.kinds import (  # noqa: F401  (the codes callers pass)
    CYLINDRICAL, EQUAL_AREA_CYLINDRICAL, EQUIRECTANGULAR, MERCATOR)


def lonlat_to_dir(phi, sin_t, cos_t, out=None) -> np.ndarray:
    """Unit directions ``(..., 3)`` of longitudes ``phi`` and latitudes given by their sine and cosine."""
    phi = np.asarray(phi, dtype=np.float64)
    d = np.empty(phi.shape + (3,), dtype=np.float64) if out is None else out
    np.multiply(np.sin(phi), cos_t, out=d[..., 0])
    d[..., 1] = sin_t
    np.multiply(np.cos(phi), cos_t, out=d[..., 2])
    return d


def dir_to_lonlat(d) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Longitude, and the latitude's sine and cosine (``dy``, ``hypot(dx, dz)``), of unit directions."""
    d = np.asarray(d, dtype=np.float64)
    dx, dy, dz = d[..., 0], d[..., 1], d[..., 2]
    return np.arctan2(dx, dz), dy, np.hypot(dx, dz)


def height_to_lat(kind: int, y, slack: float = 0.0):
    """``(sin(theta), cos(theta), ok)`` of the latitude at height ``y`` of a cylinder; ``ok`` False where
    the spacing has no latitude (``|y| > 1`` equal-area, ``|y| > pi/2`` equirectangular, beyond
    ``slack``: those are clipped to the pole) or ``y`` is not finite."""
    y = np.asarray(y, dtype=np.float64)
    if kind == EQUIRECTANGULAR:
        t = np.clip(y, -0.5 * np.pi, 0.5 * np.pi)
        return np.sin(t), np.cos(t), np.abs(y) <= 0.5 * np.pi * (1.0 + slack)
    if kind == CYLINDRICAL:
        c = 1.0 / np.sqrt(1.0 + y * y)
        return y * c, c, np.isfinite(y)
    if kind == EQUAL_AREA_CYLINDRICAL:
        s = np.clip(y, -1.0, 1.0)
        return s, np.sqrt(np.maximum(1.0 - s * s, 0.0)), np.abs(y) <= 1.0 + slack
    if kind == MERCATOR:
        return np.tanh(y), 1.0 / np.cosh(y), np.isfinite(y)
    raise ValueError(f"not a cylindrical projection code: {kind}")


def lat_to_height(kind: int, s, c):
    """Height ``y`` of the latitude with sine ``s`` and cosine ``c >= 0``, and whether it is finite
    (the poles of the central cylinder and of Mercator are at infinity)."""
    s = np.asarray(s, dtype=np.float64)
    if kind == EQUIRECTANGULAR:
        return np.arctan2(s, c), np.ones(s.shape, dtype=bool)
    if kind == EQUAL_AREA_CYLINDRICAL:
        return np.array(s, dtype=np.float64, copy=True), np.ones(s.shape, dtype=bool)
    ok = np.asarray(c) > 0
    t = np.divide(s, c, out=np.zeros(s.shape), where=ok)
    if kind == CYLINDRICAL:
        return t, ok
    if kind == MERCATOR:  # atanh(s) = asinh(s / c): accurate near the poles, where 1 - s loses digits
        return np.arcsinh(t), ok
    raise ValueError(f"not a cylindrical projection code: {kind}")
