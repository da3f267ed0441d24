"""NumPy references of the lens models' compiled kernels (``lenslab.cxx_kernels``, ``src/native/lens_*``).

Each function takes the arguments of the kernel of the same name, without its output arrays, and returns
what the kernel writes: ``(out, ok)`` (and the largest iteration count where the kernel returns one). They
are composed from the NumPy formulas of this package (the whole-image models' kernels, ``perspective_pixels``,
``hammer_pixels`` and ``tiled_pixels``, have theirs in the models' own NumPy steps of ``dir_to_pixel``, which run
when the kernel is switched off; ``cubemap_pixels`` has ``Cubemap._dir_to_pixel`` and ``eac_pixels`` ``EquiAngularCubemap._dir_to_pixel``) (:mod:`.azimuthal`, :mod:`.lonlat`, :mod:`.calibrated`,
:mod:`.radial`) and solve with :func:`.solve.invert_increasing`, the vectorised form of the kernels' Newton;
OCamCalib's radius is solved here on the angle ``atan2(rho, -pol(rho))`` itself, where the kernel solves the
sign of a sine. ``tests/lenses/test_native_lens_kernels.py`` holds each kernel to its reference. They are for
tests, not speed: each makes the temporaries the kernels avoid.
"""

from __future__ import annotations

import numpy as np

from lenslab.lenses.formulas import azimuthal, calibrated, lonlat
from lenslab.lenses.formulas.kinds import CYLINDRICAL, EQUAL_AREA_CYLINDRICAL, EQUIRECTANGULAR, MERCATOR, RECTILINEAR
from lenslab.lenses.formulas.solve import invert_increasing

F = np.float64
CYLINDERS = (EQUIRECTANGULAR, CYLINDRICAL, EQUAL_AREA_CYLINDRICAL, MERCATOR)


def unit(d) -> tuple[np.ndarray, np.ndarray]:
    """Rows of ``d`` scaled to unit length, and which rows are finite and not zero (the others: zero)."""
    d = np.asarray(d, dtype=F).reshape(-1, 3)
    n2 = np.einsum("ij,ij->i", d, d)
    good = (n2 > 0.0) & np.isfinite(n2)
    with np.errstate(all="ignore"):
        u = d / np.sqrt(n2)[:, None]
    return np.where(good[:, None], u, 0.0), good


def _finish(x, y, ok):
    ok = ok & np.isfinite(x) & np.isfinite(y)
    return np.stack([np.where(ok, x, 0.0), np.where(ok, y, 0.0)], -1), ok


def _store(u, v, ok, width, height, slack):
    """The image test of the kernels: within ``slack`` px of the edges counts, moved onto them."""
    ok = ok & (u >= -slack) & (u <= width + slack) & (v >= -slack) & (v <= height + slack)
    return _finish(np.clip(u, 0.0, width), np.clip(v, 0.0, height), ok)


def equirect_pixels(d, p):
    """Equirect directions -> pixels; ``p``: W, H, lon_min, lon_max, lat_min, lat_max (radians), full sphere,
    wraps, edge slack."""
    w, h, lon0, lon1, lat0, lat1, full, wraps, e = (float(v) for v in p)
    u, good = unit(d)
    phi, s, c = lonlat.dir_to_lonlat(u)
    theta = np.arctan2(s, c)
    if full:
        return _finish((phi / np.pi + 1.0) * (0.5 * w), (1.0 - theta / (np.pi / 2)) * (0.5 * h), good)
    if not wraps:
        phi = np.where(phi < lon0, phi + 2 * np.pi, phi)
    return _store((phi - lon0) / (lon1 - lon0) * w, (lat1 - theta) / (lat1 - lat0) * h, good, w, h, e)


def fisheye_dirs(xy, p):
    """Fisheye pixels -> unit directions and validity; ``p``: W, H, H / W, mapping code, plane scale, the
    largest squared radius (rim slack included), cx, cy, r_ref, whether (cx, cy, r_ref) move the circle."""
    w, h, aspect, kind, scale, s_max2, cx, cy, r_ref, local = (float(v) for v in p)
    xy = np.asarray(xy, dtype=F).reshape(-1, 2)
    with np.errstate(all="ignore"):
        u = 2.0 * xy[:, 0] / w - 1.0
        v = (1.0 - 2.0 * xy[:, 1] / h) * (aspect if w != h else 1.0)
        if local:
            u, v = (u - cx) / r_ref, (v - cy) / r_ref
        d, _ = azimuthal.plane_to_dir(int(kind), u * scale, v * scale)
        ok = (u * u + v * v <= s_max2) & np.isfinite(xy[:, 0] ** 2 + xy[:, 1] ** 2) & np.isfinite((d * d).sum(-1))
    return np.where(ok[:, None], d, 0.0), ok


def _solve(f, t, hi, x0, settings):
    """``f(x) = t`` on ``[0, hi]`` for the elements of ``t`` (NaN where not converged); ``settings``: the
    kernels' (tol, residual tolerance, residual ulps, max_iter), of which the NumPy solve takes the first and
    last (the others are its own constants, :func:`.solve.kernel_settings`)."""
    x, conv = invert_increasing(f, np.asarray(t, dtype=F), 0.0, hi, np.asarray(x0, dtype=F), tol=settings[0],
                                max_iter=int(settings[3]))
    return np.where(conv, x, np.nan), conv


def _guess(t, table, step, sqrt_map=False):
    g = np.sqrt(t) if sqrt_map else t
    return np.interp(g / step, np.arange(len(table)), table)


def division_unbend(uv, k1, k2, hi, f_hi, strict, pole, table, step, *settings):
    """Division model: undistorted ``(u, v)`` -> image ``(u, v)``, solving ``r_u = r_d / (1 + k1 r_d^2 + k2 r_d^4)``
    (past a pole, its reciprocal ``-1/r_u``)."""
    uv = np.asarray(uv, dtype=F).reshape(-1, 2)
    t = np.hypot(uv[:, 0], uv[:, 1])
    inside = (t < f_hi) if strict else (t <= f_hi)
    recip = pole & (t > 1.0)

    def den(x):
        s = x * x
        return 1.0 + s * (k1 + k2 * s), 1.0 - s * (k1 + 3.0 * k2 * s)

    def direct(x):
        dd, num = den(x)
        return np.where(dd > 0.0, x / dd, np.inf), np.where(dd > 0.0, num / (dd * dd), 0.0)

    def reciprocal(x):
        dd, num = den(x)
        return -dd / x, num / (x * x)

    r = np.full(t.shape, np.nan)
    with np.errstate(all="ignore"):
        for sel, f, tt in ((inside & ~recip, direct, t), (inside & recip, reciprocal, -1.0 / t)):
            if sel.any():
                r[sel] = _solve(f, tt[sel], hi, _guess(t[sel], table, step), settings)[0]
        s = r * r
        scale = 1.0 + s * (k1 + k2 * s)
    return _finish(uv[:, 0] * scale, uv[:, 1] * scale, inside & np.isfinite(r))


def brown_bend(uv, k1, k2, hi, rd_fold, table, step, *settings):
    """Brown polynomial: image ``(u, v)`` -> undistorted, solving ``r_d = r_u (1 + k1 r_u^2 + k2 r_u^4)``."""
    uv = np.asarray(uv, dtype=F).reshape(-1, 2)
    t = np.hypot(uv[:, 0], uv[:, 1])
    ok = t < rd_fold
    r = np.full(t.shape, np.nan)
    if ok.any():
        r[ok] = _solve(lambda x: (x * (1.0 + x * x * (k1 + k2 * x * x)), 1.0 + x * x * (3.0 * k1 + 5.0 * k2 * x * x)),
                       t[ok], hi, _guess(t[ok], table, step), settings)[0]
    with np.errstate(all="ignore"):
        scale = np.where(t > 0.0, r / t, 1.0)
    return _finish(uv[:, 0] * scale, uv[:, 1] * scale, ok & np.isfinite(r))


def tan_fisheye_dir_to_uv(d, F_, hi, psi_max, strict, table, step, *settings):
    """Tan-fold fisheye: direction -> ``(u, v)``, solving ``psi(r) = theta`` (the angle of
    ``(r sin(tan(F r)), cos(tan(F r)))``, kept increasing past the fold)."""
    d = np.asarray(d, dtype=F).reshape(-1, 3)
    rho = np.hypot(d[:, 0], d[:, 1])
    theta = np.arctan2(rho, d[:, 2])
    inside = (theta < psi_max) if strict else (theta <= psi_max)

    def psi(x):
        t = np.tan(x * F_)
        st, ct = np.sin(t), np.cos(t)
        y = x * st
        a = np.arctan2(y, ct)
        return np.where(y < 0.0, a + 2.0 * np.pi, a), (st * ct + x * F_ * (1.0 + t * t)) / (ct * ct + y * y)

    r = np.full(theta.shape, np.nan)
    if inside.any():
        r[inside] = _solve(psi, theta[inside], hi, _guess(theta[inside], table, step, sqrt_map=True), settings)[0]
    with np.errstate(all="ignore"):
        k = np.where(rho > 0.0, r / rho, 0.0)
    return _finish(d[:, 0] * k, d[:, 1] * k, inside & np.isfinite(r))


def distort(x, y, a, b, p1, p2, s):
    """OpenCV's distortion of points and its Jacobian ``(xd, yd, j11, j12, j21, j22)``."""
    r2 = x * x + y * y
    num = 1.0 + r2 * (a[0] + r2 * (a[1] + r2 * (a[2] + r2 * a[3])))
    dnum = a[0] + r2 * (2.0 * a[1] + r2 * (3.0 * a[2] + r2 * 4.0 * a[3]))
    den = 1.0 + r2 * (b[0] + r2 * (b[1] + r2 * b[2]))
    dden = b[0] + r2 * (2.0 * b[1] + r2 * 3.0 * b[2])
    R, dR = num / den, (dnum * den - num * dden) / (den * den)
    xd = x * R + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x) + s[0] * r2 + s[1] * r2 * r2
    yd = y * R + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y + s[2] * r2 + s[3] * r2 * r2
    dsx, dsy = s[0] + 2.0 * s[1] * r2, s[2] + 2.0 * s[3] * r2
    j11 = R + 2.0 * x * x * dR + 2.0 * p1 * y + 6.0 * p2 * x + 2.0 * x * dsx
    j12 = 2.0 * x * y * dR + 2.0 * p1 * x + 2.0 * p2 * y + 2.0 * y * dsx
    j21 = 2.0 * x * y * dR + 2.0 * p1 * x + 2.0 * p2 * y + 2.0 * x * dsy
    j22 = R + 2.0 * y * y * dR + 6.0 * p1 * y + 2.0 * p2 * x + 2.0 * y * dsy
    return xd, yd, j11, j12, j21, j22


def distort_points(x, y, a, b, p1, p2, s, tangential, fold):
    """OpenCV's distortion inside the fold (with a positive Jacobian when tangential): ``(xd, yd, ok)``."""
    x, y = np.asarray(x, dtype=F), np.asarray(y, dtype=F)
    with np.errstate(all="ignore"):
        xd, yd, j11, j12, j21, j22 = distort(x, y, a, b, p1, p2, s)
        ok = x * x + y * y < fold * fold
        if tangential:
            ok &= j11 * j22 - j12 * j21 > 0.0
    return np.where(ok, xd, 0.0), np.where(ok, yd, 0.0), ok


def _cv_rays(d):
    u, good = unit(d)
    return u[:, 0], -u[:, 1], u[:, 2], good


def calibrated_project(d, kind, q, a, b, p1, p2, s, dist, tangential, fold, fx, fy, skew, cx, cy, width, height,
                       slack):
    """Calibrated model: lenslab directions -> pixels (projection, distortion, intrinsics, image test)."""
    X, Y, Z, good = _cv_rays(d)
    with np.errstate(all="ignore"):
        mx, my, ok = calibrated.project(kind, X, Y, Z, q)
    ok &= good
    if dist:
        with np.errstate(all="ignore"):
            mx, my, ok2 = distort_points(mx, my, a, b, p1, p2, s, tangential, fold)
        ok &= ok2
    return _store(fx * mx + skew * my + cx + 0.5, fy * my + cy + 0.5, ok, width, height, slack)


def undistort(xd, yd, a, b, p1, p2, s, tangential, fold, hi, f_hi, strict, table, step, settings, tol_2d, max_iter_2d):
    """Undistorted points ``(x, y, ok)``: the radial solve, then (tangential) the 2-D Newton with its steps
    halved to stay inside the fold."""
    rd = np.hypot(xd, yd)
    h2 = hi * hi
    lim = f_hi + (((3.0 * (abs(p1) + abs(p2)) + abs(s[0]) + abs(s[2])) * h2 + (abs(s[1]) + abs(s[3])) * h2 * h2)
                  if tangential else 0.0)
    ok = (rd < lim) if strict else (rd <= lim)
    rr = np.where(rd < f_hi, rd, f_hi * (1.0 - 1e-9))
    r = np.full(rd.shape, np.nan)
    zero = np.zeros(1)

    def f(x):
        xd_, _, j11, *_ = distort(x, np.zeros_like(x), a, b, 0.0, 0.0, zero.repeat(4))
        return xd_, j11

    if ok.any():
        r[ok] = _solve(f, rr[ok], hi, _guess(rr[ok], table, step), settings)[0]
    with np.errstate(all="ignore"):
        ok &= np.isfinite(r)
        if strict:
            ok &= r < fold
        k = np.where(rd > 0.0, r / rd, 1.0)
        x, y = xd * k, yd * k
        if not tangential:
            return x, y, ok
        done = np.zeros(ok.shape, dtype=bool)
        run = ok.copy()
        for _ in range(max_iter_2d):
            fx_, fy_, j11, j12, j21, j22 = distort(x, y, a, b, p1, p2, s)
            ex, ey = fx_ - xd, fy_ - yd
            conv = run & (np.hypot(ex, ey) <= tol_2d * np.maximum(1.0, rd))
            done |= conv
            run &= ~conv
            if not run.any():
                break
            det = j11 * j22 - j12 * j21
            sx, sy = (j22 * ex - j12 * ey) / det, (j11 * ey - j21 * ex) / det
            step_ = np.ones(x.shape)
            for _ in range(30):
                out = (x - step_ * sx) ** 2 + (y - step_ * sy) ** 2 >= fold * fold
                if not out.any():
                    break
                step_ = np.where(out, 0.5 * step_, step_)
            x = np.where(run, x - step_ * sx, x)
            y = np.where(run, y - step_ * sy, y)
        _, _, j11, j12, j21, j22 = distort(x, y, a, b, p1, p2, s)
        ok = done & (j11 * j22 - j12 * j21 > 0.0) & (x * x + y * y < fold * fold)
    return x, y, ok


def calibrated_unproject(xy, kind, q, a, b, p1, p2, s, dist, tangential, fold, hi, f_hi, strict, table, step, tol,
                         res_tol, rel_ulps, max_iter, tol_2d, max_iter_2d, fx, fy, skew, cx, cy):
    """Calibrated model: lenslab pixels -> unit directions ``(d, ok)``."""
    xy = np.asarray(xy, dtype=F).reshape(-1, 2)
    with np.errstate(all="ignore"):
        my = (xy[:, 1] - 0.5 - cy) / fy
        mx = (xy[:, 0] - 0.5 - cx - skew * my) / fx
    ok = np.isfinite(mx) & np.isfinite(my)
    mx, my = np.where(ok, mx, 0.0), np.where(ok, my, 0.0)
    if dist:
        mx, my, ok2 = undistort(mx, my, a, b, p1, p2, s, tangential, fold, hi, f_hi, strict, table, step,
                                (tol, res_tol, rel_ulps, max_iter), tol_2d, max_iter_2d)
        ok &= ok2
    with np.errstate(all="ignore"):
        X, Y, Z, ok3 = calibrated.unproject(kind, mx, my, q)
    ok &= ok3
    d = np.stack([X, -Y, Z], -1)
    return np.where(ok[:, None], d, 0.0), ok


def ocam_project(d, pol_unit, rho_hi, a_hi, strict, table, step, tol, res_tol, rel_ulps, max_iter, c, dd, e, xc, yc,
                 width, height, slack):
    """OCamCalib: lenslab directions -> pixels, solving ``atan2(rho, -pol(rho)) = theta`` for ``rho`` on
    ``[0, rho_hi]`` (the kernel's ``pol_unit(u) = pol(u rho_hi) / rho_hi`` in rising powers; ``table`` in
    ``rho``). The kernel's solve is in ``u``: its ``tol`` is ``rho_hi`` times this one's."""
    pol = np.asarray(pol_unit, dtype=F) / float(rho_hi) ** (np.arange(len(pol_unit)) - 1.0)
    X, Y, Z, good = _cv_rays(d)
    lat = np.hypot(X, Y)
    t = np.arctan2(lat, Z)
    ok = good & ((t < a_hi) if strict else (t <= a_hi))
    P = np.polynomial.polynomial

    def angle(r):
        p, dp = P.polyval(r, pol), P.polyval(r, P.polyder(pol))
        return np.arctan2(r, -p), (-p + r * dp) / (r * r + p * p)

    rho = np.full(t.shape, np.nan)
    if ok.any():
        rho[ok] = _solve(angle, t[ok], rho_hi, _guess(t[ok], table, step), (tol * rho_hi, 0, 0, max_iter))[0]
    ok &= np.isfinite(rho)
    with np.errstate(all="ignore"):
        k = np.where(lat > 0.0, rho / lat, 0.0)
    xp, yp = Y * k, X * k
    return _store(e * xp + yp + yc + 0.5, c * xp + dd * yp + xc + 0.5, ok, width, height, slack)


def lensfun_dir_to_pixel(d, kind, f, coeffs, r_lim, cx, cy, norm):
    """lensfun profile: directions -> pixels, unbounded by the image."""
    u, good = unit(d)
    with np.errstate(all="ignore"):
        if kind == RECTILINEAR:
            ok = u[:, 2] > 0.0
            x, y = f * u[:, 0] / u[:, 2], f * u[:, 1] / u[:, 2]
        elif kind in CYLINDERS:
            phi, s, c = lonlat.dir_to_lonlat(u)
            h, ok = lonlat.lat_to_height(kind, s, c)
            x, y = phi * f, h * f
        else:
            p, _, ok = azimuthal.dir_to_plane(kind, u)
            back = (u[:, 0] * u[:, 0] + u[:, 1] * u[:, 1] == 0) & (u[:, 2] < 0)  # rho 0 in float64, behind
            ok = ok & ~back  # the back pole: a circle, not a pixel
            x, y = p[:, 0] * f, p[:, 1] * f
        qx, qy = x, -y
        r = np.hypot(qx, qy)
        ok = ok & good & (r <= r_lim)
        scale = np.polynomial.polynomial.polyval(r, np.asarray(coeffs, dtype=F))
        return _finish(qx * scale / norm + cx, qy * scale / norm + cy, ok)
