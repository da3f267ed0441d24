"""Named presets of other models that 360 users ask for by name: half-equirect (VR180) and little-planet."""

from __future__ import annotations

import numpy as np

from lenslab.lenses.core.base import FLOAT, DirKernel, Lens, Param, PixelKernel, ReferencePoint
from lenslab.lenses.projections.equirect import Equirect
from lenslab.lenses.projections.fisheye import Fisheye
from lenslab.lenses.registry import register


@register
class HalfEquirect(Equirect):
    r"""Half equirectangular (180-degree VR, "VR180"): the front hemisphere, longitude and latitude linear.

    Longitudes -90..90 and latitudes -90..90: ``phi = (2x/W - 1) pi/2``, ``theta = (1 - 2y/H) pi/2``. Square
    frames have square pixels. v360's ``hequirect``; the same as
    ``equirect:lon_min=-90,lon_max=90``.
    """

    name = "half-equirect"
    #: specs and image sizes the conformance tests run on (round trips, extremes)
    examples = (
        ('half-equirect', (8192, 8192)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways)
    reference_points = (
        ReferencePoint('half-equirect', (512, 512), (400.25, 100.5),
                       (0.44760486816173956, 0.8158144108067338, 0.36619220242650385),
                       'ffmpeg v360 hequirect: longitude and latitude -90..90, float64'),
    )
    summary = "half equirectangular (VR180): the front hemisphere, longitude and latitude linear"
    params = ()
    lon_min, lon_max, lat_min, lat_max = -90.0, 90.0, -90.0, 90.0

    def v360_dir_to_pixel(self, d):
        """Where v360 reads this frame as its input: behind the camera, clamped to the nearer edge column."""
        from lenslab.lenses.formulas import lonlat

        phi, s, c = lonlat.dir_to_lonlat(d)
        px = np.stack([(np.clip(phi / np.pi, -0.5, 0.5) + 0.5) * self.width,
                       (0.5 - np.arctan2(s, c) / np.pi) * self.height], axis=-1)
        return px, np.isfinite(px).all(axis=-1)


#: lens axes of the little planet in camera space: image right = +x, image up = +z (forward), the
#: optical axis = -y (straight down); rows are the lens's x, y and z axes
DOWN = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])


@register
class LittlePlanet(Lens):
    r"""Little planet: a stereographic fisheye looking straight down, forward (+z) at the top.

    The nadir is at the image centre, the horizon a circle round it and the sky outside.

    ``d_lens = D d`` with ``D`` the rotation whose rows are (+x, +z, -y): the lens's axis is -y. Then
    ``fisheye:mapping=stereographic`` with the given fov across the width (270 by default: the horizon
    at ``r = tan(45 deg) / tan(67.5 deg) = 0.414`` of the half width).
    """

    name = "little-planet"
    #: specs and image sizes the conformance tests run on (round trips, extremes)
    examples = (
        ('little-planet', (8192, 8192)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways)
    reference_points = (
        ReferencePoint('little-planet', (512, 512), (300.5, 150.25),
                       (0.38666135368867766, 0.07862794502678755, 0.9188637787096103),
                       'stereographic r = 2 f tan(theta/2) looking down (-y), forward (+z) at the top'),
    )
    #: (true spec, perturbed start, fitted parameters) a fit recovers exactly, on a 256 x 192 image
    fit_examples = (
        ('little-planet:fov=250', 'little-planet:fov=230', 'fov'),
    )
    summary = "little planet: a stereographic fisheye looking straight down, forward at the top"
    #: how ffmpeg's v360 reads this projection as its input (lenslab.warp.compat_v360)
    v360_read = "span"  # v360 sg with pitch=-90
    params = (
        Param("fov", 270.0, "field of view across the image width, degrees (below 360)", 0.0, 360.0,
              lo_open=True, hi_open=True),
    )

    def _check(self) -> None:
        self._fisheye = Fisheye(self.width, self.height, fov=self.fov, mapping="stereographic")

    def uv_to_dir(self, uv):
        d, ok = self._fisheye.uv_to_dir(uv)
        return d @ DOWN, ok  # camera = D^T lens

    #: v360 reads a direction its ``sg`` input does not see from the input's top-left pixel
    v360_unseen = "top-left"

    def v360_dir_to_pixel(self, d):
        """Where v360 reads this frame as its input (``sg`` looking down): the stereographic fisheye's reading,
        the frame's corners included (:meth:`Fisheye.v360_dir_to_pixel` of the turned direction)."""
        return self._fisheye.v360_dir_to_pixel(np.ascontiguousarray(np.asarray(d, dtype=FLOAT) @ DOWN.T))

    def v360_pixel_to_dir(self, xy):
        """The rays v360 (``sg`` with ``pitch=-90``) gives this frame's pixels (:mod:`lenslab.lenses.core.v360`):
        the stereographic formula carried on past the horizon's field of view into the frame's corners."""
        from lenslab.lenses.core import v360

        def carried_on(uv):
            d, ok = self._fisheye.v360_uv_to_dir(uv)
            return d @ DOWN, ok

        return v360.continued(self, xy, carried_on)

    def dir_kernel(self):
        """The compiled ``pixel -> dir``: the fisheye's (``fisheye_dirs``) turned by ``D^T``
        (``turned_fisheye_dirs``)."""
        from lenslab.lenses.core.native import dir_kernel_holds, lens_kernels

        kern = self._fisheye.dir_kernel()
        if kern is None or not dir_kernel_holds(self, LittlePlanet):
            return None
        return DirKernel(lens_kernels().turned_fisheye_dirs, np.concatenate([kern.params, DOWN.reshape(9)]))

    def pixel_kernel(self):
        """The compiled ``dir -> pixel``: the fisheye's (``fisheye_pixels``) seeing ``D d``."""
        from lenslab.lenses.core.native import kernel_holds, lens_kernels

        if not kernel_holds(self, LittlePlanet):
            return None
        return PixelKernel(lens_kernels().fisheye_pixels, self._fisheye.pixel_params(DOWN))

    def dir_to_uv(self, d):
        return self._fisheye.dir_to_uv(np.ascontiguousarray(d @ DOWN.T, dtype=FLOAT))
