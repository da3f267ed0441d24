"""Compiled (numba) ``dir -> pixel`` of the equirect model, imported on first use (numba stays out of
start-up): the warp engine's :class:`~lenslab.lenses.core.protocol.PixelKernel` of an equirect source."""

from __future__ import annotations

import numba
import numpy as np

from lenslab.lenses.formulas.kinds import EQUIRECTANGULAR
from lenslab.lenses.formulas.lonlat_kernels import dir_to_lon_height


@numba.njit(cache=True, nogil=True)
def equirect_pixel(dx, dy, dz, p):
    """:meth:`Equirect.dir_to_pixel` for one unit direction, the same operations in the same order
    (``p``: W, H, lon_min, lon_max, lat_min, lat_max in radians, full sphere, wraps, edge slack)."""
    w, h = p[0], p[1]
    phi, theta, _ = dir_to_lon_height(EQUIRECTANGULAR, dx, dy, dz)
    if p[6] != 0.0:
        x = phi / np.pi
        x += 1.0
        x *= 0.5 * w
        y = theta / (np.pi / 2)
        y = 1.0 - y
        y *= 0.5 * h
        return x, y, True
    lon0, lon1, lat0, lat1 = p[2], p[3], p[4], p[5]
    if p[7] == 0.0 and phi < lon0:
        phi += 2 * np.pi
    x = (phi - lon0) / (lon1 - lon0) * w
    y = (lat1 - theta) / (lat1 - lat0) * h
    e = p[8]
    if not (x >= -e and x <= w + e and y >= -e and y <= h + e):
        return 0.0, 0.0, False
    return min(max(x, 0.0), w), min(max(y, 0.0), h), True
