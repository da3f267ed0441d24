"""Compiled (numba) direction -> pixel of a lensfun profile: projection, distortion and the pixel frame
in one pass per direction, no temporary arrays. Imported on first use (numba stays out of start-up).

The inverses of :func:`lenslab.lenses.lensfun_profile.plane_to_dir` (per lensfun type) and the forward
map of :class:`lenslab.lenses.radial.Radial` (round trips and lensfun itself check them in the tests).
"""

from __future__ import annotations

import math

import numba

#: projection codes of the kernel, by lensfun type
KINDS = {"rectilinear": 0, "equirectangular": 1, "panoramic": 2, "fisheye": 3, "equisolid": 4,
         "stereographic": 5, "orthographic": 6, "thoby": 7}
THOBY_K1, THOBY_K2 = 1.47, 0.713


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
        if kind == 0:
            if not dz > 0.0:
                continue
            x = f * dx / dz
            y = f * dy / dz
        elif kind == 1:
            x = f * math.atan2(dx, dz)
            y = f * math.asin(min(1.0, max(-1.0, dy)))
        elif kind == 2:
            h = math.hypot(dx, dz)
            if not h > 0.0:
                continue
            x = f * math.atan2(dx, dz)
            y = f * dy / h
        else:
            sxy = math.hypot(dx, dy)
            theta = math.atan2(sxy, dz)
            if kind == 3:
                rho = f * theta
            elif kind == 4:
                if not theta < math.pi:
                    continue
                rho = 2.0 * f * math.sin(0.5 * theta)
            elif kind == 5:
                if not theta < math.pi:
                    continue
                rho = 2.0 * f * math.tan(0.5 * theta)
            elif kind == 6:
                if not theta <= 0.5 * math.pi:
                    continue
                rho = f * math.sin(theta)
            else:
                if not THOBY_K2 * theta <= 0.5 * math.pi:
                    continue
                rho = THOBY_K1 * f * math.sin(THOBY_K2 * theta)
            k = rho / sxy if sxy > 0.0 else 0.0
            x = dx * k
            y = dy * k
        qx = x
        qy = -y  # lensfun's plane: y down
        r = math.hypot(qx, qy)
        if not r <= r_lim:
            continue
        p = 0.0
        for j in range(coeffs.shape[0] - 1, -1, -1):  # Horner: P(r)
            p = p * r + coeffs[j]
        out[i, 0] = qx * p / norm + cx
        out[i, 1] = qy * p / norm + cy
        valid[i] = True
