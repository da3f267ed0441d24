"""ffmpeg v360's pixel mapping, for matching footage already converted with it.

ffmpeg's v360 filter puts each output sample at the *corner* of its pixel (``(2 i / W - 1)`` for
column ``i``) and reads the input with the centre of pixel ``i`` at coordinate ``i`` (``u = (phi / pi
+ 1) W / 2``, taps at ``floor(u)`` and ``floor(u) + 1``). In lenslab's terms (centres at ``+0.5`` on
both sides) that is an output offset of ``-1/2`` pixel and an input offset of ``+1/2`` pixel: the two
cancel when the sizes are equal, and disagree by up to half a source pixel when they are not (a 2x
reduction of an equirect reads source pixel ``2 i`` instead of the average of ``2 i`` and ``2 i + 1``).
Its equirect input clamps at the poles instead of continuing across them.

:func:`v360_plan` reproduces those conventions with lenslab's lens models and exact filters. It does
not reproduce v360's other habits (clamping float input to [0, 1], leaving fisheye corners unmasked,
its own bicubic/Lanczos weights): the output keeps HDR values and alpha.
"""

from __future__ import annotations

import numpy as np

from lenslab.errors import WarpError
from lenslab.lenses import Camera
from lenslab.warp.engine import WarpPlan
from lenslab.warp.maps import MapBand
from lenslab.warp.seam import Border


class V360Plan(WarpPlan):
    """A :class:`WarpPlan` with v360's sample positions (see the module docstring)."""

    def __init__(self, src_camera: Camera, dst_camera: Camera, **options):
        if options.get("samples", 1) != 1 or options.get("antialias", False):
            raise WarpError("--compat v360 reproduces v360's one sample per pixel; drop --samples/--antialias")
        if getattr(dst_camera.lens, "name", "") == "tiled":
            raise WarpError("--compat v360 has no tiled outputs; warp each view separately")
        super().__init__(src_camera, dst_camera, **options)
        self.border = Border(self.border.wrap, False, False)  # v360 clamps rows at the poles

    def _offsets(self, r0: int, r1: int) -> np.ndarray:
        # samples at the pixel corners; a hair below them, so that the top row of an equirect output keeps
        # its longitude (v360's float32 cos(pi/2) is not 0 either) instead of landing on the pole itself
        return np.array([[0.0, 1e-9]])

    def _band(self, r0: int, r1: int) -> MapBand:
        band = self.mapper.map_band(r0, r1, self._offsets(r0, r1))
        band.xs[band.valid] += np.float32(0.5)  # the input's pixel centres at integer coordinates
        band.ys[band.valid] += np.float32(0.5)
        return band


def v360_plan(src_camera: Camera, dst_camera: Camera, **options) -> V360Plan:
    """A plan mapping pixels as ffmpeg's v360 does; run it with ``plan.run(image)``."""
    return V360Plan(src_camera, dst_camera, **options)


__all__ = ["V360Plan", "v360_plan"]
