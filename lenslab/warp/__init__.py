"""The resampling engine: reproject an image from one lens into another, HDR in, HDR out.

``lenslab.warp.warp(image, src_camera, dst_camera, filter="bilinear", samples=1, antialias=False)``
returns ``(image, alpha)``: float32, never clamped, colour premultiplied by the coverage ``alpha``
(the OpenEXR convention), exactly 0 where no sample lands on the source. See :func:`warp`.

Modules: :mod:`~lenslab.warp.maps` (where each output sample reads the source: computed in float64,
kept as float32 index coordinates) and :mod:`~lenslab.warp.lattice` (its interpolated lattice),
:mod:`~lenslab.warp.filters` (exact nearest/bilinear/bicubic/Lanczos samplers), :mod:`~lenslab.warp.seam`
(seams, poles and piece edges), :mod:`~lenslab.warp.antialias` and :mod:`~lenslab.warp.pyramid` (footprint
prefilter), :mod:`~lenslab.warp.optics` (per-channel lenses, falloff), :mod:`~lenslab.warp.given` (warping
by a map from elsewhere), :mod:`~lenslab.warp.batch` (one cached map for many images),
:mod:`~lenslab.warp.engine` (the banded loop), :mod:`~lenslab.warp.tiles` (outputs made of
camera tiles), :mod:`~lenslab.warp.kernels.native` (the samplers compiled ahead of time,
C++ in ``src/native``) and :mod:`~lenslab.warp.kernels.reference` (their NumPy references, for the tests).
"""

from __future__ import annotations

import sys
import types

from lenslab.errors import WarpError
from lenslab.warp.engine import WarpPlan, warp
from lenslab.warp.filters import FILTERS
from lenslab.warp.given import warp_with_map
from lenslab.warp.maps import ParallaxWarning, check_eyes, exact_map
from lenslab.warp.multiview import warp_tiles
from lenslab.warp.tiles import tile_cameras

__all__ = ["warp", "warp_with_map", "warp_tiles", "tile_cameras", "WarpPlan", "WarpError", "ParallaxWarning", "FILTERS",
           "check_eyes", "exact_map"]


class _CallableModule(types.ModuleType):
    """Lets ``lenslab.warp(...)`` call :func:`warp` even once this package has been imported."""

    def __call__(self, *args, **kwargs):
        return warp(*args, **kwargs)


sys.modules[__name__].__class__ = _CallableModule
