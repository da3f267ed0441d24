"""What the calibrated-camera models share: OpenCV's pixel and camera frames, intrinsics, scaling.

Calibrated models (``opencv``, ``kannala-brandt``, ``omnidir``, ``double-sphere``, ``eucm``,
``ocam``) take the numbers of the tool that calibrated them verbatim: intrinsics in pixels of the
calibration image (``width`` x ``height``, part of the spec), the tool's parameter names. Their
equations work in OpenCV's frames, and this module converts at the boundary:

- pixels: OpenCV puts pixel centres at integer coordinates, lenslab at ``x + 0.5``; so lenslab's
  ``(x, y)`` is OpenCV's ``(x - 0.5, y - 0.5)``;
- camera space: OpenCV's ``(X right, Y down, Z forward)`` is lenslab's ``(x, -y, z)``.

A model is a projection to a normalised plane, ``(X, Y, Z) -> (mx, my)``, an optional distortion of
that plane (:class:`~lenslab.lenses.calibrated.polydistort.PolyDistortion`), and the affine intrinsics
``u = fx mx + skew my + cx``, ``v = fy my + cy``. Subclasses name their projection for the compiled
kernels of both directions (:attr:`kernel_kind`, :meth:`kernel_params`;
``src/native/lens_formulas.h``, where the closed forms are) and give :meth:`make_distortion`
when they distort; a model of another shape (``ocam``) overrides the pixel-level methods.

A lens built for another image size scales the intrinsics about the image's corner (lenslab's frame):
``fx' = fx sx``, ``cx' + 0.5 = (cx + 0.5) sx`` with ``sx = W' / width`` (``y`` likewise).
"""

from __future__ import annotations

from typing import Any, ClassVar

import numpy as np

from lenslab.errors import LensError
from lenslab.lenses.core.base import FLOAT, MAX_SIDE, Lens, Param, as_points, check_size

SIZE_PARAMS = (
    Param("width", 0, "calibration image width in px; the intrinsics are in its pixels (0: this image's; "
          "the default intrinsics are those of a 1000 x 1000 image)", 0, MAX_SIDE),
    Param("height", 0, "calibration image height in px (0: this image's)", 0, MAX_SIDE),
)
#: the image the default intrinsics describe (a spec that gives none of them is scaled from it)
DEFAULT_CALIBRATION = (1000, 1000)


def intrinsics_params(fx: float, fy: float, cx: float, cy: float) -> tuple[Param, ...]:
    """The pinhole intrinsics, OpenCV's names and pixel convention (pixel centres at integers)."""
    return (
        Param("fx", fx, "focal length along x, px of the calibration image", 0.0, None, lo_open=True),
        Param("fy", fy, "focal length along y, px", 0.0, None, lo_open=True),
        Param("cx", cx, "principal point x, px; OpenCV's pixel centres (lenslab's x - 0.5)"),
        Param("cy", cy, "principal point y, px (lenslab's y - 0.5)"),
    )


def coefficient_params(names: str, doc: str) -> tuple[Param, ...]:
    return tuple(Param(n, 0.0, doc) for n in names.split())


class Calibrated(Lens):
    """A calibrated camera: projection, distortion, intrinsics; OpenCV's frames inside."""

    sensor_frame = True  # its intrinsics are the stored image's pixels

    #: names of the parameters scaled like ``fx`` (x) and ``fy`` (y) for another image size
    x_scaled: ClassVar[tuple[str, ...]] = ("fx",)
    y_scaled: ClassVar[tuple[str, ...]] = ("fy",)
    #: the parameters in pixels of the calibration image: a spec giving none of them (and no size)
    #: takes the defaults, which describe a :data:`DEFAULT_CALIBRATION` image
    intrinsic_names: ClassVar[tuple[str, ...]] = ("fx", "fy", "cx", "cy")
    #: the intrinsics' skew parameter name (``u = fx mx + skew my + cx``), if the model has one
    skew_name: ClassVar[str | None] = None

    def __init__(self, width: int, height: int, /, **values: Any):
        # Lens.__init__ with the calibration size among the parameters: the intrinsics are first
        # scaled to this image, whose size the ``width`` and ``height`` parameters then equal
        self.width, self.height = check_size(width, height)
        known = {p.name for p in self.params}
        unknown = sorted(set(values) - known)
        if unknown:
            raise LensError(f"{self.name}: unknown parameter(s) {', '.join(unknown)}; valid: {', '.join(known)}")
        values = self.scaled_values(self.width, self.height, values)
        for p in self.params:
            if p.name not in ("width", "height"):
                setattr(self, p.name, p.convert(self.name, values.get(p.name, p.default)))
        self._check()

    @classmethod
    def scaled_values(cls, width: int, height: int, values: dict[str, Any]) -> dict[str, Any]:
        """The parameter values for a ``width x height`` image, given values for their own ``width``,
        ``height`` (the calibration size; 0 or absent: this image's)."""
        params = {p.name: p for p in cls.params}
        values = dict(values)
        if not ({"width", "height"} | set(cls.intrinsic_names)) & set(values):
            values["width"], values["height"] = DEFAULT_CALIBRATION  # the defaults' own image
        cw = params["width"].convert(cls.name, values.get("width", 0)) or width
        ch = params["height"].convert(cls.name, values.get("height", 0)) or height
        values["width"], values["height"] = int(width), int(height)
        if (cw, ch) == (width, height):
            return values
        sx, sy = width / cw, height / ch
        got = {k: params[k].convert(cls.name, values.get(k, params[k].default)) for k in params
               if k not in ("width", "height")}
        values.update(cls.scale(got, sx, sy))
        return values

    @classmethod
    def scale(cls, v: dict[str, float], sx: float, sy: float) -> dict[str, float]:
        """Intrinsics for pixels ``sx`` x ``sy`` times as many (about the image's corner)."""
        out = {}
        for k in cls.x_scaled + ((cls.skew_name,) if cls.skew_name else ()):
            out[k] = v[k] * sx
        for k in cls.y_scaled:
            out[k] = v[k] * sy
        out["cx"] = (v["cx"] + 0.5) * sx - 0.5
        out["cy"] = (v["cy"] + 0.5) * sy - 0.5
        return out

    def _check(self) -> None:
        self.distortion = self.make_distortion()
        if self.distortion is not None:  # the inverse's bracket: twice the image's farthest corner
            u = np.array([-0.5, self.width - 0.5, -0.5, self.width - 0.5])
            v = np.array([-0.5, -0.5, self.height - 0.5, self.height - 0.5])
            mx, my = self.pixel_to_plane(u, v)
            self.distortion.prepare(2.0 * float(np.hypot(mx, my).max()))

    # -- hooks -----------------------------------------------------------------------------------
    def make_distortion(self):
        """The distortion of the normalised plane (None: none)."""
        return None

    # -- affine intrinsics -------------------------------------------------------------------------
    @property
    def skew(self) -> float:
        return float(getattr(self, self.skew_name)) if self.skew_name else 0.0

    def pixel_to_plane(self, u, v):
        """OpenCV pixel -> distorted normalised point."""
        my = (v - self.cy) / self.fy
        mx = (u - self.cx - self.skew * my) / self.fx
        return mx, my

    # -- lenslab's interface ---------------------------------------------------------------------
    def pixel_to_dir(self, xy):
        from lenslab.lenses.core.native import lens_kernels, run_rows
        from lenslab.lenses.calibrated.polydistort import MAX_ITER_2D, TOL_2D
        from lenslab.lenses.formulas.solve import kernel_settings

        xy = as_points(xy, 2, "pixel coordinates")
        dist = self.distortion
        if dist is None:  # a model without distortion: the solve's arguments are unused
            from lenslab.lenses.calibrated.polydistort import PolyDistortion

            dist = PolyDistortion()
            dist.prepare(1.0)
        table, step = dist.ready().table

        def fill(flat, d, ok):
            worst = lens_kernels().calibrated_unproject(
                flat, self.kernel_kind, np.array(self.kernel_params() + (0.0,), dtype=FLOAT), dist.a, dist.b, dist.p1,
                dist.p2, dist.s, self.distortion is not None and not dist.identity, not dist.radial_only, dist.fold,
                dist.hi, dist.f_hi, dist.strict, table, step, *kernel_settings(), TOL_2D, MAX_ITER_2D,
                self.fx, self.fy, self.skew, self.cx, self.cy, d, ok)
            if self.distortion is not None:
                self.distortion.max_iterations = worst

        return run_rows(xy, 3, fill)

    #: the compiled projection (a code of lenslab.lenses.formulas.kinds) of the model's dir_to_pixel
    kernel_kind: ClassVar[int | None] = None

    def kernel_params(self) -> tuple[float, ...]:
        """The projection's parameters ``q`` for the compiled kernel."""
        return ()

    def dir_to_pixel(self, dirs):
        from lenslab.lenses.core.native import lens_kernels, run_rows

        d = as_points(dirs, 3, "directions")
        dist = self.distortion
        none = dist is None or dist.identity
        a, b, s = (np.zeros(4), np.zeros(3), np.zeros(4)) if dist is None else (dist.a, dist.b, dist.s)
        return run_rows(d, 2, lambda flat, xy, ok: lens_kernels().calibrated_project(
            flat, self.kernel_kind, np.array(self.kernel_params() + (0.0,), dtype=FLOAT), a, b,
            0.0 if dist is None else dist.p1, 0.0 if dist is None else dist.p2, s,
            not none, bool(dist is not None and not dist.radial_only),
            np.inf if dist is None else dist.fold, self.fx, self.fy, self.skew, self.cx, self.cy,
            float(self.width), float(self.height), self.edge_slack, xy, ok))

    @property
    def solver_iterations(self) -> dict[str, int]:
        """The largest iteration count of the last solved inverse, by side (``p2d``/``d2p``)."""
        if self.distortion is not None and not self.distortion.identity:
            return {"p2d": self.distortion.max_iterations}
        return {}

    def dir_to_pixel_unit(self, d):
        return self.dir_to_pixel(d)


def unit_rows(X, Y, Z):
    """``(X, Y, Z)`` scaled to unit length (zero stays zero)."""
    n = np.sqrt(X * X + Y * Y + Z * Z)
    inv = np.where(n > 0, 1.0 / np.where(n > 0, n, 1.0), 0.0)
    return X * inv, Y * inv, Z * inv
