"""Dual fisheye: two fisheye lenses back to back, side by side in one frame (consumer 360 cameras)."""

from __future__ import annotations

import numpy as np

from lenslab.lenses.core.base import FLOAT, Lens, Param, Piece, PixelKernel, ReferencePoint
from lenslab.lenses.projections.fisheye import FOV_LIMITS, RIM_SLACK, Fisheye
from lenslab.lenses.registry import register

#: camera -> back-lens frame: the front lens turned half a turn about +y (its right is -x)
BACK = np.diag([-1.0, 1.0, -1.0])


@register
class DualFisheye(Lens):
    r"""Two fisheyes back to back, side by side: the front lens (axis +z) and the back lens.

    The back lens looks along -z, turned half a turn about +y (its image right is -x); each lens fills
    one half of the frame.

    Each half of width ``W/2`` is one :class:`~lenslab.lenses.projections.fisheye.Fisheye` with the given ``fov``
    and ``mapping``, its circle inscribed in the half's width: ``u_h = 2 (x - x_0) / (W/2) - 1``,
    ``v_h = (1 - 2y/H) H / (W/2)``. ``front`` says which half holds the front lens (v360's
    ``dfisheye`` puts it on the right).

    :meth:`dir_to_pixel` reads a direction from the lens whose axis is nearer (the front one for
    ``dz >= 0``): with ``fov >= 180`` every direction is seen, from a point no more than 90 degrees off
    that lens's axis. As a warp source (:meth:`source_views`) the overlap is blended:
    :meth:`blend_views` gives both readings of a direction with weights that fall smoothly to 0 at each
    circle's rim and sum to 1, so the seam leaves no step. As an output each half is
    one fisheye, overlap included.
    """

    name = "dual-fisheye"
    #: specs and image sizes the conformance tests run on (round trips, extremes)
    examples = (
        ('dual-fisheye:fov=190', (8192, 4096)),
        ('dual-fisheye:fov=180,mapping=equisolid,front=right', (8192, 4096)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways)
    reference_points = (
        ReferencePoint('dual-fisheye:fov=190', (800, 400), (150.5, 220.25),
                       (-0.3970564797309939, -0.1624321962535885, 0.9033061128564706),
                       'two equidistant fisheyes back to back (ffmpeg v360 dfisheye): the front lens, a = r fov/2'),
    )
    #: (true spec, perturbed start, fitted parameters) a fit recovers exactly, on a 256 x 192 image
    fit_examples = (
        ('dual-fisheye:fov=175', 'dual-fisheye:fov=160', 'fov'),
    )
    summary = "two fisheyes back to back, side by side (front and back lens)"
    #: how ffmpeg's v360 reads this projection as its input (lenslab.warp.compat_v360)
    v360_read = "span-halves"
    #: the frame the model fills, width / height (the default output size of lenslab warp)
    frame_aspect = 2.0
    params = (
        Param("fov", 190.0, "field of view of each lens across its half of the frame, degrees", 0.0, 360.0,
              lo_open=True),
        Param("mapping", "equidistant", "angle-from-axis mapping of both lenses", choices=tuple(FOV_LIMITS)),
        Param("front", "left", "half of the frame holding the front lens", choices=("left", "right")),
    )

    def _check(self) -> None:
        self._lens = Fisheye(max(1, self.width // 2), self.height, fov=self.fov, mapping=self.mapping)
        self.half = self.width / 2.0
        self._front_x0 = 0.0 if self.front == "left" else self.half

    def pieces(self):
        """The two halves, one lens each; nothing lies across their edges (taps stay in their half)."""
        return (Piece(0.0, 0.0, self.half, float(self.height)), Piece(self.half, 0.0, self.half, float(self.height)))

    def pixel_to_dir(self, xy):
        return self._halves_to_dir(xy, self._lens.uv_to_dir)

    def v360_pixel_to_dir(self, xy):
        """The rays v360 gives this output's pixels: each lens's formula carried on outside its circle
        (:meth:`Fisheye.v360_uv_to_dir`)."""
        return self._halves_to_dir(xy, self._lens.v360_uv_to_dir)

    def _halves_to_dir(self, xy, uv_to_dir):
        from lenslab.lenses.core.base import as_points, clean

        xy = as_points(xy, 2, "pixel coordinates")
        with np.errstate(all="ignore"):
            x, y = xy[..., 0], xy[..., 1]
            right = x >= self.half
            back = right if self.front == "left" else ~right
            x0 = np.where(right, self.half, 0.0)
            uv = np.empty(xy.shape, dtype=FLOAT)
            uv[..., 0] = 2.0 * (x - x0) / self.half - 1.0
            uv[..., 1] = (1.0 - 2.0 * y / self.height) * (self.height / self.half)
            d, ok = uv_to_dir(uv)
            flip = np.where(back, -1.0, 1.0)  # the back lens: half a turn about +y (x and z change sign)
            d[..., 0] *= flip
            d[..., 2] *= flip
            ok &= self.in_image(xy) & np.isfinite(x) & np.isfinite(y)
        return clean(d, ok, inplace=True)

    def pixel_kernel(self):
        """The compiled ``dir -> pixel`` (``dual_fisheye_pixels``: the NumPy steps of :meth:`dir_to_pixel`, in their
        order)."""
        from lenslab.lenses.core.native import kernel_holds, lens_kernels

        fish = self._lens
        if not kernel_holds(self, DualFisheye, ("_dir_to_pixel",)) or type(fish) is not Fisheye:
            return None
        return PixelKernel(lens_kernels().dual_fisheye_pixels, np.array(
            [self.width, self.height, self.half, fish.kind, fish.plane_scale, fish.s_max * (1.0 + RIM_SLACK),
             self._front_x0, self.edge_slack, self.half / self.height, self.half * (1.0 - 1e-15)], dtype=FLOAT))

    def dir_to_pixel(self, dirs):
        from lenslab.lenses.core.native import dir_to_pixel_through

        return dir_to_pixel_through(self, dirs, self._dir_to_pixel)

    def _dir_to_pixel(self, d):
        """The NumPy steps of :meth:`dir_to_pixel` (float64 directions of any length)."""
        from lenslab.lenses.core.base import clean

        n = np.sqrt(np.einsum("...i,...i->...", d, d))
        good = (n > 0) & np.isfinite(n)
        local = d / np.where(good, n, 1.0)[..., None]
        back = local[..., 2] < 0
        # into the back lens's frame, in place: x and z change sign (a multiply by -1 is exact)
        flip = np.where(back, -1.0, 1.0)
        local[..., 0] *= flip
        local[..., 2] *= flip
        uv, ok = self._lens.dir_to_uv(local)
        x0 = flip  # the left edge of each direction's half, in the flip array's place
        x0 *= 0.5 * self.half - self._front_x0  # back: half - front x0, front: front x0
        x0 -= 0.5 * self.half
        np.negative(x0, out=x0)
        xy = np.empty(d.shape[:-1] + (2,), dtype=FLOAT)
        x, y = xy[..., 0], xy[..., 1]
        np.add(uv[..., 0], 1.0, out=x)
        x *= 0.5
        x *= self.half
        x += x0
        np.multiply(uv[..., 1], self.half / self.height, out=y)
        np.subtract(1.0, y, out=y)
        y *= 0.5
        y *= self.height
        # a point on the shared edge belongs to the right half: keep the left lens's points off it
        np.copyto(x, np.minimum(x, self.half * (1.0 - 1e-15)), where=x0 == 0.0)
        ok &= good & self.snap_to_image(xy)
        return clean(xy, ok, inplace=True)

    def blend_views(self, dirs):
        """Both lenses' pixels for each direction, with blend weights: ``[(xy, valid, weight), ...]``
        (front lens, then back lens; float64, weight 0 where that lens does not see the direction).

        With ``a`` the angle from a lens's axis and ``F = fov/2``, its margin ``m = F - a`` falls to 0 at
        its rim; across the overlap (``2F - 180`` degrees wide) the two margins sum to its width, and
        each weight is the smoothstep ``w^2 (3 - 2w)`` of ``w = m / (2F - pi)``: continuous with its
        slope, 1/2 each at 90 degrees, 0 at each rim, and the two sum to 1. Without an overlap
        (``fov <= 180``) a direction's one lens weighs 1.
        """
        from lenslab.lenses.core.base import as_points, clean

        d = as_points(dirs, 3, "directions")
        with np.errstate(all="ignore"):
            n = np.sqrt(np.einsum("...i,...i->...", d, d))
            good = (n > 0) & np.isfinite(n)
            d = d / np.where(good, n, 1.0)[..., None]
            band = 2.0 * self._lens.F - np.pi
            views = []
            for back, x0 in ((False, self._front_x0), (True, self.half - self._front_x0)):
                local = d @ BACK if back else d
                uv, ok = self._lens.dir_to_uv(local)
                xy = np.empty(d.shape[:-1] + (2,), dtype=FLOAT)
                xy[..., 0] = (uv[..., 0] + 1.0) * 0.5 * self.half + x0
                xy[..., 1] = (1.0 - uv[..., 1] * (self.half / self.height)) * 0.5 * self.height
                if x0 == 0.0:  # the shared edge belongs to the right half
                    xy[..., 0] = np.minimum(xy[..., 0], self.half * (1.0 - 1e-15))
                ok &= good & self.snap_to_image(xy)
                a = np.arctan2(np.hypot(local[..., 0], local[..., 1]), local[..., 2])
                if band > 0:
                    w = np.clip((self._lens.F - a) / band, 0.0, 1.0)
                    w = w * w * (3.0 - 2.0 * w)
                else:
                    w = np.ones(a.shape)
                w = np.where(ok, w, 0.0)
                xy, ok = clean(xy, ok, inplace=True)
                views.append((xy, ok, w))
            total = views[0][2] + views[1][2]
            for _, ok, w in views:
                np.divide(w, total, out=w, where=total > 0)
                ok &= w > 0
        return views

    def source_view_count(self) -> int:
        """Two readings per direction where the circles overlap (``fov > 180``), else one."""
        return 2 if self._lens.F > np.pi / 2 else 1

    def source_views(self, dirs):
        """As a source, the overlap is blended: :meth:`blend_views` (one view, the nearer lens's
        :meth:`dir_to_pixel`, without an overlap)."""
        if self.source_view_count() == 1:
            return super().source_views(dirs)
        return self.blend_views(dirs)
