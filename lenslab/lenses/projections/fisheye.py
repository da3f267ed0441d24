"""Fisheye lenses: equidistant, equisolid, stereographic and orthographic mappings."""

from __future__ import annotations

import numpy as np

from lenslab.errors import LensError
from lenslab.lenses.core import v360
from lenslab.lenses.core.base import DirKernel, Field, Lens, Param, PixelKernel, ReferencePoint, clean
from lenslab.lenses.formulas import azimuthal
from lenslab.lenses.registry import register

#: largest fov (degrees) each mapping allows, and whether that bound itself is allowed
FOV_LIMITS = {
    "equidistant": (360.0, True),   # a = r F reaches the back pole (-z) at the rim
    "equisolid": (360.0, True),     # 2 asin(r sin(F/2)) reaches pi at F = 180
    "stereographic": (360.0, False),  # tan(F/2) diverges at F = 180
    "orthographic": (180.0, True),  # asin(r sin F) only sees the front hemisphere
}

#: slack on the rim test of the inverse: a direction exactly on the rim comes back at r = 1 to a few
#: ulps, and must still count as seen (1e-12 of the radius is 4e-9 px at 8192 px width)
RIM_SLACK = 1e-12
RIM_R2 = (1.0 + RIM_SLACK) ** 2  # both directions accept r <= 1 + RIM_SLACK, so rim points round-trip


@register
class Fisheye(Lens):
    r"""Fisheye lens, angle from the axis a function of the image radius: ``a = g(r)``.

    With ``r = sqrt(u^2 + v^2)`` and ``F = fov/2``::

        equidistant    a = r F
        equisolid      a = 2 asin(r sin(F/2))      (equal areas hold equal solid angles)
        stereographic  a = 2 atan(r tan(F/2))
        orthographic   a = asin(r sin F)            (F <= 90 deg)
        d = (sin(a) u/r, sin(a) v/r, cos(a))        (d = +z at r = 0: the limit, no division)

    Valid for ``r <= 1`` (to 1e-12, so that rim points survive rounding both ways): the image circle
    touches the left and right edges, so a pixel on that rim is ``fov/2`` from the axis. Allowed fov: equidistant and equisolid up to 360 (the rim is then the
    back pole -z), stereographic below 360, orthographic up to 180.

    Full-frame and off-centre fisheyes: the field of view may instead be given across the image height
    (``vfov``: ``a = vfov/2`` at ``r = H/W``) or its diagonal (``dfov``: ``a = dfov/2`` at
    ``r = hypot(1, H/W)``); ``r`` is then divided by that radius before ``g``. Such a lens is masked only
    where its mapping ends (equidistant at 180 degrees from the axis, equisolid where ``r sin(F/2)``
    reaches 1, orthographic at 90 degrees; stereographic never), not at the image's width. ``cx`` and
    ``cy`` move the centre of the circle from the image centre, in the units of ``(u, v)`` (half the image
    width; ``cy`` up): ``r = sqrt((u - cx)^2 + (v - cy)^2)``.

    The inverse uses ``rho = sqrt(dx^2 + dy^2)`` and ``dz`` (no trigonometry except equidistant's
    ``atan2``): equisolid ``r = rho / (sin(F/2) sqrt(2 (1 + dz)))``, stereographic
    ``r = rho / (tan(F/2) (1 + dz))`` (each with the complementary form behind the camera, where
    ``1 + dz`` cancels), orthographic ``r = rho / sin F`` for ``dz >= 0``; ``(u, v) = (dx, dy) r / rho``.
    """

    name = "fisheye"
    #: specs and image sizes the conformance tests run on (round trips, extremes)
    examples = (
        ('fisheye:fov=180,mapping=equidistant', (8192, 8192)),
        ('fisheye:fov=360,mapping=equidistant', (8192, 8192)),
        ('fisheye:fov=180,mapping=equisolid', (8192, 8192)),
        ('fisheye:fov=360,mapping=equisolid', (8192, 8192)),
        ('fisheye:fov=270,mapping=stereographic', (8192, 8192)),
        ('fisheye:fov=180,mapping=orthographic', (8192, 6000)),
        ('fisheye:dfov=180', (8192, 5461)),
        ('fisheye:vfov=150,mapping=equisolid,cx=0.05,cy=-0.02', (8192, 5461)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways)
    reference_points = (
        ReferencePoint('fisheye:fov=180,mapping=equisolid', (512, 512), (400.25, 130.5),
                       (0.6766798510869233, 0.5887231979993682, 0.4421644210815432),
                       'equisolid r = 2 f sin(theta/2) (Kannala and Brandt 2006, table 1), float64'),
        ReferencePoint('fisheye:fov=200,mapping=stereographic', (512, 512), (400.25, 130.5),
                       (0.7493526741090939, 0.6519498135229899, 0.11589655065138435),
                       'stereographic r = 2 f tan(theta/2) (Kannala and Brandt 2006, table 1), float64'),
    )
    #: (true spec, perturbed start, fitted parameters) a fit recovers exactly, on a 256 x 192 image
    fit_examples = (
        ('fisheye:fov=200,mapping=equidistant', 'fisheye:fov=170,mapping=equidistant', 'fov'),
        ('fisheye:fov=180,mapping=equisolid', 'fisheye:fov=200,mapping=equisolid', 'fov'),
        ('fisheye:fov=150,mapping=stereographic', 'fisheye:fov=130,mapping=stereographic', 'fov'),
        ('fisheye:fov=120,mapping=orthographic', 'fisheye:fov=100,mapping=orthographic', 'fov'),
    )
    summary = "fisheye lens: equidistant, equisolid, stereographic or orthographic mapping"
    params = (
        Param("fov", 180.0, "field of view across the image width (the image circle), degrees; "
              "up to 360 for equidistant and equisolid, below 360 stereographic, up to 180 orthographic",
              0.0, 360.0, lo_open=True),
        Param("mapping", "equidistant", "angle-from-axis mapping a = g(r)",
              choices=tuple(FOV_LIMITS)),
        Param("vfov", 0.0, "field of view across the image height instead of fov, degrees (0: use fov); "
              "masked only where the mapping ends", 0.0, 360.0),
        Param("dfov", 0.0, "field of view across the image diagonal instead of fov, degrees (0: use fov), "
              "e.g. a full-frame fisheye; masked only where the mapping ends", 0.0, 360.0),
        Param("cx", 0.0, "centre of the image circle right of the image centre, in half image widths"),
        Param("cy", 0.0, "centre of the image circle above the image centre, in half image widths"),
    )
    #: parameters left out of the spec when they hold these values (so that older specs read the same)
    quiet_defaults = {"vfov": 0.0, "dfov": 0.0, "cx": 0.0, "cy": 0.0}

    @property
    def v360_read(self) -> str | None:
        """How ffmpeg's v360 reads this fisheye as its input (it has no off-centre circle)."""
        return "span" if self.cx == 0.0 and self.cy == 0.0 else None

    def _check(self) -> None:
        given = [name for name in ("vfov", "dfov") if getattr(self, name) > 0]
        if len(given) > 1:
            raise LensError("fisheye: give one of fov, vfov and dfov, not vfov and dfov together")
        if given and self.fov != 180.0:
            raise LensError(f"fisheye: give one of fov, vfov and dfov, not fov={self.fov:g} and {given[0]} together")
        key = given[0] if given else "fov"
        angle = getattr(self, key)
        hi, closed = FOV_LIMITS[self.mapping]
        if angle > hi or (angle == hi and not closed):
            bound = f"<= {hi:g}" if closed else f"< {hi:g}"
            raise LensError(
                f"fisheye: {key}={angle:g} is too wide for the {self.mapping} mapping (it needs {key} {bound}); "
                f"use a narrower {key}, or mapping=equidistant (up to 360)"
            )
        self.F = np.radians(angle) / 2.0
        #: normalised radius at which the angle from the axis is F: the half width, height or diagonal
        self.r_ref = {"fov": 1.0, "vfov": self.aspect, "dfov": float(np.hypot(1.0, self.aspect))}[key]
        #: largest radius (over r_ref) with a ray: the image width for fov, else where the mapping ends
        self.s_max = 1.0 if key == "fov" else mapping_end(self.mapping, self.F)
        self._s_max2 = (self.s_max * (1.0 + RIM_SLACK)) ** 2
        self.kind = azimuthal.AZIMUTHAL[self.mapping]
        #: plane radius (unit focal length) of r = 1: the mapping's s at F
        self.plane_scale = float(azimuthal.radius_of_angle(self.kind, self.F))

    def spec(self) -> str:
        text = super().spec()  # (its quiet_defaults left out)
        name, _, rest = text.partition(":")
        keep = rest.split(",")
        if self.vfov > 0 or self.dfov > 0:
            keep = [p for p in keep if not p.startswith("fov=")]
        return name + ":" + ",".join(keep)

    def _to_local(self, uv):
        """(u, v) relative to the circle's centre, over r_ref (a new array only when it differs)."""
        if self.cx == 0.0 and self.cy == 0.0 and self.r_ref == 1.0:
            return uv
        out = uv - (self.cx, self.cy)
        out /= self.r_ref
        return out

    def _from_local(self, uv):
        if self.cx == 0.0 and self.cy == 0.0 and self.r_ref == 1.0:
            return uv
        uv *= self.r_ref
        uv += (self.cx, self.cy)
        return uv

    # -- pixel -> direction ------------------------------------------------------------------
    def dir_kernel(self):
        """The compiled ``pixel -> dir`` (``fisheye_dirs``: the NumPy steps of :meth:`uv_to_dir` through
        :meth:`Lens.pixel_to_dir`, in their order)."""
        from lenslab.lenses.core.native import dir_kernel_holds, lens_kernels

        if not dir_kernel_holds(self, Fisheye, ("_to_local",)):
            return None
        local = not (self.cx == 0.0 and self.cy == 0.0 and self.r_ref == 1.0)
        return DirKernel(lens_kernels().fisheye_dirs, np.array(
            [self.width, self.height, self.aspect, self.kind, self.plane_scale, self._s_max2, self.cx, self.cy,
             self.r_ref, local], dtype=np.float64))

    def uv_to_dir(self, uv):
        uv = self._to_local(uv)
        # the plane at unit focal length is (u, v) scaled by s(F): r = 1 lies at F from the axis
        c = self.plane_scale
        d, _ = azimuthal.plane_to_dir(self.kind, uv[..., 0] * c, uv[..., 1] * c)
        r2 = uv[..., 0] * uv[..., 0] + uv[..., 1] * uv[..., 1]
        return d, r2 <= self._s_max2

    def v360_uv_to_dir(self, uv):
        """:meth:`uv_to_dir` as ffmpeg's v360 carries it on past the image circle: equidistant and stereographic
        everywhere (equidistant past the back pole), equisolid to the back pole, orthographic to 90 degrees."""
        c = self.plane_scale
        uv = self._to_local(uv)
        d, ok = azimuthal.plane_to_dir(self.kind, uv[..., 0] * c, uv[..., 1] * c)
        return d, ok | (self.kind == azimuthal.EQUIDISTANT)

    def v360_pixel_to_dir(self, xy):
        """The rays v360 gives this fisheye's output pixels (:mod:`lenslab.lenses.core.v360`): :meth:`v360_uv_to_dir`,
        and orthographic past 90 degrees the forward direction."""
        return v360.continued(self, xy, self.v360_uv_to_dir, v360.FORWARD if self.mapping == "orthographic" else None)

    # -- direction -> pixel ------------------------------------------------------------------
    def pixel_kernel(self):
        """The compiled ``dir -> pixel`` (``fisheye_pixels``: the NumPy steps of :meth:`dir_to_uv` through
        :meth:`Lens.dir_to_pixel`, in their order)."""
        from lenslab.lenses.core.native import kernel_holds, lens_kernels

        if not kernel_holds(self, Fisheye, ("_from_local",)):
            return None
        return PixelKernel(lens_kernels().fisheye_pixels, self.pixel_params())

    def field(self):
        """A lens whose ``fov`` spans its image circle sees no further than ``fov/2`` from its axis (+z): one cone,
        a micro-radian wider (the rim test's slack is 1e-12 of the radius). With ``vfov`` or ``dfov`` the circle
        reaches as far as the mapping does, and the bound is the frame's: none is given."""
        from lenslab.lenses.core.native import kernel_holds

        if self.vfov > 0 or self.dfov > 0 or not kernel_holds(self, Fisheye, ("_from_local",)):
            return None
        return Field(np.array([[0.0, 0.0, 1.0]]), np.array([self.F + 1e-6]))

    def pixel_params(self, turn=None) -> np.ndarray:
        """The parameters of ``fisheye_pixels`` for this lens, seeing ``turn @ d`` (a 3 x 3 rotation; None: ``d``)."""
        local = not (self.cx == 0.0 and self.cy == 0.0 and self.r_ref == 1.0)
        head = [self.width, self.height, self.aspect, self.kind, self.plane_scale, self.s_max * (1.0 + RIM_SLACK),
                local, self.cx, self.cy, self.r_ref, self.edge_slack, turn is not None]
        rows = np.zeros(9) if turn is None else np.asarray(turn, dtype=np.float64).reshape(9)
        return np.concatenate([np.array(head, dtype=np.float64), rows])

    #: as v360's input, a direction outside the frame reads the top-left pixel (lenslab.lenses.core.v360)
    v360_unseen = v360.TOP_LEFT

    def v360_dir_to_pixel(self, d):
        """Where v360 reads this fisheye as its input (continuous pixel coordinates, float64 ``(..., 2)``) and whether
        it sees the direction (unit ``(..., 3)``): anywhere in the frame, the corners outside the image circle
        included (orthographic: the front hemisphere). Measured on ffmpeg 5.1: its equidistant input tests
        ``0 <= x < W`` itself, the other mappings the position they read at (``x (W - 1) / W``, see
        :mod:`lenslab.warp.compat_v360`), a pixel's width further out."""
        xy, _, seen = azimuthal.dir_to_plane(self.kind, d)
        xy /= self.plane_scale
        px = self.uv_to_pixel(self._from_local(xy))
        w, h = float(self.width), float(self.height)
        if self.mapping != "equidistant":
            w, h = w * w / max(w - 1.0, 1.0), h * h / max(h - 1.0, 1.0)
        with np.errstate(invalid="ignore"):
            ok = (px[..., 0] >= 0) & (px[..., 0] < w) & (px[..., 1] >= 0) & (px[..., 1] < h)
            ok &= seen | (self.mapping != "orthographic")
        return clean(px, ok, inplace=True)

    def dir_to_uv(self, d):
        xy, s, seen = azimuthal.dir_to_plane(self.kind, d)
        xy /= self.plane_scale
        valid = s / self.plane_scale <= self.s_max * (1.0 + RIM_SLACK)
        if self.mapping == "orthographic":
            valid &= seen
        return self._from_local(xy), valid


def mapping_end(mapping: str, F: float) -> float:
    """Radius (in units of the radius where the angle is F) at which a mapping ends: equidistant at
    180 degrees from the axis, equisolid where r sin(F/2) = 1 (180 degrees), orthographic at 90 degrees;
    stereographic reaches 180 degrees only at infinity (a large finite radius stands for it)."""
    kind = azimuthal.AZIMUTHAL[mapping]
    return float(min(azimuthal.largest_radius(kind) / azimuthal.radius_of_angle(kind, F), 1e6))
