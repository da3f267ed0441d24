"""Compiled (numba) direction -> pixel of a lensfun profile: projection, distortion and the pixel frame
in one pass per direction, no temporary arrays. Imported on first use (numba stays out of start-up).

The inverses of :func:`lenslab.lenses.lensfun.profile.plane_to_dir` (per lensfun type; the fisheye
mappings are :func:`lenslab.lenses.formulas.azimuthal_kernels.dir_to_plane`, the cylinders
:func:`lenslab.lenses.formulas.lonlat_kernels.dir_to_lon_height`) and the forward map of
:class:`lenslab.lenses.formulas.radial.Radial` (round trips and lensfun itself check them in the tests).
"""

from __future__ import annotations

import math

import numba

from lenslab.lenses.formulas import azimuthal_kernels as az
from lenslab.lenses.formulas import lonlat_kernels as ll
from lenslab.lenses.formulas.kinds import CYLINDRICAL, EQUIRECTANGULAR, RECTILINEAR
from lenslab.lenses.formulas.radial_kernels import poly_scale


@numba.njit(cache=True, error_model="numpy")
def dir_to_pixel(d, kind, f, coeffs, r_lim, cx, cy, norm, out, valid):
    """Unit-or-not directions ``d`` (n, 3) -> pixels ``out`` (n, 2) and ``valid`` (n,), unbounded by the
    image. ``coeffs``: the distortion's ``P(r)`` in rising powers (``[1.0]`` for none), one-to-one up to
    ``r_lim``; ``(cx, cy)`` the lens centre in pixels, ``norm`` normalised units per pixel."""
    for i in range(d.shape[0]):
        out[i, 0] = 0.0
        out[i, 1] = 0.0
        valid[i] = False
        dx, dy, dz = d[i, 0], d[i, 1], d[i, 2]
        n = math.sqrt(dx * dx + dy * dy + dz * dz)
        if not (n > 0.0 and n < math.inf):
            continue
        dx /= n
        dy /= n
        dz /= n
        if kind == RECTILINEAR:
            if not dz > 0.0:
                continue
            x = f * dx / dz
            y = f * dy / dz
        elif kind == EQUIRECTANGULAR or kind == CYLINDRICAL:
            x, y, seen = ll.dir_to_lon_height(kind, dx, dy, dz)
            if not seen:
                continue
            x *= f
            y *= f
        else:  # the fisheye mappings (lenslab.lenses.formulas.kinds codes)
            x, y, seen = az.dir_to_plane(kind, dx, dy, dz)
            if not seen:
                continue
            x *= f
            y *= f
        qx = x
        qy = -y  # lensfun's plane: y down
        r = math.hypot(qx, qy)
        if not r <= r_lim:
            continue
        p = poly_scale(coeffs, r)
        out[i, 0] = qx * p / norm + cx
        out[i, 1] = qy * p / norm + cy
        valid[i] = True
