"""The pinhole (rectilinear) camera."""

from __future__ import annotations

import numpy as np

from lenslab.lenses.core.base import DirKernel, Field, Lens, Param, PixelKernel, ReferencePoint
from lenslab.lenses.registry import register


@register
class Perspective(Lens):
    r"""Pinhole perspective projection; straight lines stay straight.

    With ``t = tan(fov/2)`` (horizontal fov across the image width)::

        d ~ (u t, v t_v, 1),  normalised,    t_v = t, or tan(vfov/2) * W/H when vfov is given

    With ``dfov`` (the field of view across the image diagonal) instead, pixels are square and
    ``t = t_v = tan(dfov/2) / hypot(1, H/W)``.

    The inverse is ``u = (dx/dz) / t``, ``v = (dy/dz) / t_v``, valid for ``dz > 0`` inside the image.
    """

    name = "perspective"
    #: specs and image sizes the conformance tests run on (round trips, extremes)
    examples = (
        ('perspective:fov=90', (8192, 4608)),
        ('perspective:fov=120,vfov=60', (8192, 4096)),
        ('perspective:dfov=100', (8192, 5461)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways)
    reference_points = (
        ReferencePoint('perspective:fov=90', (640, 480), (500.5, 100.25),
                       (0.4591963959448755, 0.3555274035085671, 0.8140877933648765),
                       'pinhole model d ~ (u tan(fov/2), v tan(fov/2), 1), float64'),
    )
    #: (true spec, perturbed start, fitted parameters) a fit recovers exactly, on a 256 x 192 image
    fit_examples = (
        ('perspective:fov=70', 'perspective:fov=50', 'fov'),
    )
    summary = "pinhole camera (rectilinear)"
    #: how ffmpeg's v360 reads this projection as its input (lenslab.warp.compat_v360)
    v360_read = "span"
    #: as v360's input, a direction this projection does not see reads the top-left pixel (lenslab.lenses.core.v360)
    v360_unseen = "top-left"
    params = (
        Param("fov", 90.0, "horizontal field of view, degrees", 0.0, 180.0, lo_open=True, hi_open=True),
        Param("vfov", 0.0, "vertical field of view, degrees (0: square pixels from fov)", 0.0, 180.0, hi_open=True),
        Param("dfov", 0.0, "diagonal field of view instead of fov, degrees, square pixels (0: use fov)",
              0.0, 180.0, hi_open=True),
    )

    def _check(self) -> None:
        from lenslab.errors import LensError

        if self.dfov > 0 and (self.vfov > 0 or self.fov != 90.0):
            raise LensError("perspective: give dfov alone (square pixels), not with fov or vfov")

    quiet_defaults = {"vfov": 0.0, "dfov": 0.0}  # 0: derived from fov (square pixels)

    def spec(self) -> str:
        if self.dfov > 0:
            from lenslab.lenses.core.base import format_number

            return f"{self.name}:dfov={format_number(self.dfov)}"
        return super().spec()

    @property
    def t(self) -> float:
        if self.dfov > 0:
            return float(np.tan(np.radians(self.dfov) / 2) / np.hypot(1.0, self.aspect))
        return float(np.tan(np.radians(self.fov) / 2))

    @property
    def tv(self) -> float:
        if self.dfov > 0:
            return self.t
        if self.vfov > 0:
            return float(np.tan(np.radians(self.vfov) / 2) / self.aspect)
        return self.t

    def dir_kernel(self):
        """The compiled ``pixel -> dir`` (``perspective_dirs``: the NumPy steps of :meth:`uv_to_dir` through
        :meth:`Lens.pixel_to_dir`, the same bits)."""
        from lenslab.lenses.core.native import dir_kernel_holds, lens_kernels

        if not dir_kernel_holds(self, Perspective):
            return None
        return DirKernel(lens_kernels().perspective_dirs,
                         np.array([self.width, self.height, self.aspect, self.t, self.tv], dtype=np.float64))

    def uv_to_dir(self, uv):
        d = np.empty(uv.shape[:-1] + (3,), dtype=np.float64)
        x, y, z = d[..., 0], d[..., 1], d[..., 2]
        np.multiply(uv[..., 0], self.t, out=x)
        np.multiply(uv[..., 1], self.tv, out=y)
        np.multiply(x, x, out=z)  # z = 1 / sqrt(x^2 + y^2 + 1), then x, y scaled by it
        z += y * y
        z += 1.0
        np.sqrt(z, out=z)
        np.divide(1.0, z, out=z)
        x *= z
        y *= z
        return d, np.ones(uv.shape[:-1], dtype=bool)

    def pixel_kernel(self):
        """The compiled ``dir -> pixel`` (``perspective_pixels``: the NumPy steps of :meth:`dir_to_pixel`)."""
        from lenslab.lenses.core.native import kernel_holds, lens_kernels

        if not kernel_holds(self, Perspective):
            return None
        return PixelKernel(lens_kernels().perspective_pixels, np.array(
            [self.width, self.height, self.t, self.tv, self.aspect, self.edge_slack], dtype=np.float64))

    #: pixels beyond the image (and its edge slack) that :meth:`field`'s frame still holds: rounding moves an
    #: edge by far less, so the frame is a bound whatever the last bits of a projection
    FIELD_MARGIN = 1.0

    def field(self):
        """The frame's four half-spaces (planes through the eye past each image edge, :attr:`FIELD_MARGIN` pixels
        beyond it): a direction seen satisfies ``a0 <= dx/dz <= a1`` and ``b0 <= dy/dz <= b1``, with the edges'
        ``u t`` and ``v t_v``; and the cone about +z through the frame's farthest corner (the planes of a narrow
        view meet far behind the eye: the cone bounds the back)."""
        from lenslab.lenses.core.native import kernel_holds

        if not kernel_holds(self, Perspective):
            return None
        m = self.edge_slack + self.FIELD_MARGIN
        (u0, v1), (u1, v0) = self.pixel_to_uv(np.array([[-m, -m], [self.width + m, self.height + m]]))
        a0, a1, b0, b1 = u0 * self.t, u1 * self.t, v0 * self.tv, v1 * self.tv
        axes = np.array([[1.0, 0.0, -a0], [-1.0, 0.0, a1], [0.0, 1.0, -b0], [0.0, -1.0, b1], [0.0, 0.0, 1.0]])
        axes /= np.linalg.norm(axes, axis=1)[:, None]
        corner = np.arctan(np.hypot(max(-a0, a1), max(-b0, b1)))  # and the cone about the axis through the corners
        return Field(axes, np.array([np.pi / 2] * 4 + [corner]))

    def dir_to_uv(self, d):
        z = d[..., 2]
        valid = z > 0
        with np.errstate(divide="ignore", invalid="ignore"):
            inv = np.divide(1.0, z)
        uv = np.empty(d.shape[:-1] + (2,), dtype=np.float64)
        np.multiply(d[..., 0], inv, out=uv[..., 0])
        np.multiply(d[..., 1], inv, out=uv[..., 1])
        uv[..., 0] /= self.t
        uv[..., 1] /= self.tv
        return uv, valid
