"""Project Aria's Fisheye624: Kannala-Brandt with six radial terms, then tangential and thin prism terms
on the distorted point (COLMAP's RAD_TAN_THIN_PRISM_FISHEYE)."""

from __future__ import annotations

import numpy as np

from lenslab.lenses.core.base import FLOAT, ReferencePoint, as_points, clean
from lenslab.lenses.calibrated import SIZE_PARAMS, Calibrated, coefficient_params, intrinsics_params
from lenslab.lenses.calibrated.kannala_brandt import equidistant_unproject
from lenslab.lenses.calibrated.polydistort import PolyDistortion
from lenslab.lenses.formulas.radial import Radial
from lenslab.lenses.registry import register

#: residual of the tangential solve on the normalised plane (1e-14 of the focal length)
TOL = 1e-14
MAX_ITER = 50
#: a calibration with Project Aria-like numbers (the examples and the pycolmap reference point)
EXAMPLE = ("fisheye624:fx=240,fy=240,cx=511.5,cy=511.5,k0=0.41,k1=-0.39,k2=-0.12,k3=1.56,k4=-1.55,k5=0.43,"
           "p0=0.0006,p1=-0.0002,s0=-0.0005,s1=0.00003,s2=0.0003,s3=-0.00005,width=1024,height=1024")


@register
class Fisheye624(Calibrated):
    r"""Fisheye624: ``theta_d = theta (1 + k0 theta^2 + k1 theta^4 + ... + k5 theta^12)``, then OpenCV's
    tangential and thin prism terms applied to the distorted point.

    In OpenCV's frame, ``theta`` the angle from the axis: ``(x, y) = theta_d (X, Y) / |(X, Y)|``;
    with ``r^2 = x^2 + y^2``, ``x' = x + 2 p1 x y + p0 (r^2 + 2 x^2) + s0 r^2 + s1 r^4``,
    ``y' = y + 2 p0 x y + p1 (r^2 + 2 y^2) + s2 r^2 + s3 r^4``; ``u = fx x' + cx``, ``v = fy y' + cy``
    (OpenCV pixels). The radial part is a :class:`~lenslab.lenses.formulas.radial.Radial` (its fold ends the
    model's range), the tangential part a :class:`~lenslab.lenses.calibrated.polydistort.PolyDistortion`; the
    inverse solves the tangential part by 2-D Newton (at most :data:`MAX_ITER` steps, residual below
    :data:`TOL`), then the radial part by the bracketed Newton. Points that do not converge, or where
    the map folds (Jacobian not positive), are invalid. Reference: Project Aria, "Camera intrinsic
    models: FisheyeRadTanThinPrism"; COLMAP's ``RadTanThinPrismFisheyeModel``.
    """

    name = "fisheye624"
    #: a spec and image size the conformance tests run on (round trips, extremes): Project Aria-like numbers
    examples = (
        (EXAMPLE, (8192, 8192)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways): pycolmap 4.2.1's
    #: ``Camera.img_from_cam`` for COLMAP's RAD_TAN_THIN_PRISM_FISHEYE with the same numbers
    #: (COLMAP's cx, cy = these + 0.5)
    reference_points = (
        ReferencePoint(EXAMPLE, (1024, 1024),
                       (787.0147979904295, 340.1618772625286),
                       (0.7155417527999327, 0.4472135954999579, 0.5366563145999494),
                       "pycolmap 4.2.1 Camera.img_from_cam, RAD_TAN_THIN_PRISM_FISHEYE, ray (0.8, -0.5, 0.6)"),
    )
    #: (true spec, perturbed start, fitted parameters) a fit recovers exactly, on a 256 x 192 image
    fit_examples = (
        ("fisheye624:fx=80,fy=80,cx=127.5,cy=95.5,k0=0.03,k1=-0.005,width=256,height=192",
         "fisheye624:fx=70,fy=70,cx=127.5,cy=95.5,k0=0,k1=0,width=256,height=192", "fx,fy,k0,k1"),
    )
    summary = ("Fisheye624 (Project Aria; COLMAP RAD_TAN_THIN_PRISM_FISHEYE): fx, fy, cx, cy, k0..k5, p0, p1, "
               "s0..s3")
    params = (
        intrinsics_params(318.3098861837907, 318.3098861837907, 499.5, 499.5)
        + coefficient_params("k0 k1 k2 k3 k4 k5", "radial coefficient of theta^3, ^5, ... ^13")
        + coefficient_params("p0 p1", "tangential coefficient on the distorted fisheye plane")
        + coefficient_params("s0 s1 s2 s3", "thin prism coefficient on the distorted fisheye plane")
        + SIZE_PARAMS
    )

    def _check(self) -> None:
        ks = [getattr(self, f"k{i}") for i in range(6)]
        coeffs = [1.0]
        for k in ks:
            coeffs += [0.0, k]
        self.radial = Radial(coeffs)
        self.theta_max = min(self.radial.r_max, np.pi)
        # OpenCV's p1 multiplies 2 x y in x' (COLMAP's p1), OpenCV's p2 the r^2 + 2 x^2 term (COLMAP's p0)
        self.tangential = PolyDistortion(p1=self.p1, p2=self.p0, s=(self.s0, self.s1, self.s2, self.s3))
        super()._check()

    def dir_to_pixel(self, dirs):
        d = as_points(dirs, 3, "directions")
        shape = d.shape[:-1]
        d = d.reshape(-1, 3)  # the compiled distortion takes 1-D arrays
        with np.errstate(all="ignore"):
            X, Y, Z = d[..., 0], -d[..., 1], d[..., 2]
            rho = np.hypot(X, Y)
            theta = np.arctan2(rho, Z)
            valid = (theta < self.theta_max) & (rho + np.abs(Z) > 0)
            scale = np.where(rho > 0, self.radial.forward(theta) / np.where(rho > 0, rho, 1.0), 1.0)
            xd, yd, ok = self.tangential.apply(X * scale, Y * scale)
            valid &= ok & self._jacobian_positive(X * scale, Y * scale)
            xy = np.stack([self.fx * xd + self.cx + 0.5, self.fy * yd + self.cy + 0.5], axis=-1)
        valid &= np.isfinite(xy).all(axis=-1)
        xy = np.where(valid[..., None], xy, 0.0).astype(FLOAT)
        valid &= self.snap_to_image(xy)
        np.copyto(xy, 0.0, where=~valid[..., None])
        return xy.reshape(shape + (2,)), valid.reshape(shape)

    def pixel_to_dir(self, xy):
        xy = as_points(xy, 2, "pixel coordinates")
        shape = xy.shape[:-1]
        xy = xy.reshape(-1, 2)
        with np.errstate(all="ignore"):
            xd, yd = self.pixel_to_plane(xy[..., 0] - 0.5, xy[..., 1] - 0.5)
            x, y, valid = self._untangle(xd, yd)
            r = np.hypot(x, y)
            theta, ok = self.radial.inverse(np.where(valid, r, 0.0))
            valid &= ok & (theta < self.theta_max)
            k = np.where(r > 0, theta / np.where(r > 0, r, 1.0), 1.0)
            X, Y, Z, ok = equidistant_unproject(x * k, y * k)
            valid &= ok
            dirs = np.stack([X, -Y, Z], axis=-1)
        dirs, valid = clean(dirs, valid, inplace=True)
        return dirs.reshape(shape + (3,)), valid.reshape(shape)

    # -- the tangential and thin prism stage -----------------------------------------------------
    def _jacobian(self, x, y):
        t = self.tangential
        p1, p2 = t.p1, t.p2
        s1, s2, s3, s4 = t.s
        r2 = x * x + y * y
        j00 = 1.0 + 2.0 * p1 * y + 6.0 * p2 * x + 2.0 * s1 * x + 4.0 * s2 * r2 * x
        j01 = 2.0 * p1 * x + 2.0 * p2 * y + 2.0 * s1 * y + 4.0 * s2 * r2 * y
        j10 = 2.0 * p1 * x + 2.0 * p2 * y + 2.0 * s3 * x + 4.0 * s4 * r2 * x
        j11 = 1.0 + 6.0 * p1 * y + 2.0 * p2 * x + 2.0 * s3 * y + 4.0 * s4 * r2 * y
        return j00, j01, j10, j11

    def _jacobian_positive(self, x, y):
        if self.tangential.identity:
            return np.ones(np.shape(x), dtype=bool)
        j00, j01, j10, j11 = self._jacobian(x, y)
        return j00 * j11 - j01 * j10 > 0

    def _untangle(self, xd, yd):
        """The point ``(x, y)`` whose tangential and prism image is ``(xd, yd)``, and convergence."""
        finite = np.isfinite(xd) & np.isfinite(yd)
        if self.tangential.identity:
            return xd, yd, finite
        x, y = np.where(finite, xd, 0.0), np.where(finite, yd, 0.0)
        done = ~finite
        for _ in range(MAX_ITER):
            fx, fy, _ok = self.tangential.apply(x, y)
            ex, ey = fx - xd, fy - yd
            done |= np.hypot(ex, ey) <= TOL * (1.0 + np.hypot(xd, yd))
            if done.all():
                break
            j00, j01, j10, j11 = self._jacobian(x, y)
            det = j00 * j11 - j01 * j10
            det = np.where(det != 0, det, 1.0)
            x = np.where(done, x, x - (j11 * ex - j01 * ey) / det)
            y = np.where(done, y, y - (j00 * ey - j10 * ex) / det)
        return x, y, done & finite & self._jacobian_positive(x, y)
