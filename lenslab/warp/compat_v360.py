"""ffmpeg v360's pixel mapping, for matching footage already converted with it.

Measured on Debian's ffmpeg 5.1 (a source whose 16-bit values encode their own coordinates, read back
through ``v360=...:interp=line``; ``tests/warp/test_v360_ffmpeg.py`` compares every shared projection both
ways), v360 samples every output projection at its pixel *centres*, as lenslab does, and reads its
input in one of three ways, each lens saying which with its ``v360_read`` attribute:

- ``"span"`` (most projections; docs/v360.md lists which lens reads which way): the projection's
  range ``[-1, 1]`` covers the span from the centre of the first pixel to the centre of the last, ``index = p (W - 1) / W`` for lenslab's continuous coordinate ``p`` (a shrink of half a
  pixel at each edge); ``"span-halves"`` (two images side by side) does that within each half of the frame;
- ``"centre"`` (the cube layouts): lenslab's own convention, ``index = p - 1/2``;
- ``"shift"``: ``index = p``, half a pixel further right and down than lenslab.

Its panorama input clamps at the poles instead of continuing across them. v360 writes every output pixel:
where an output projection has no ray of its own (a fisheye's corners, an EAC's padding) it carries its
formulas on or samples a fixed direction, which each such lens gives as ``v360_pixel_to_dir``
(:mod:`lenslab.lenses.core.v360`; :func:`v360_output`). :class:`V360Plan` reproduces these conventions
with lenslab's lens models and filters. It does not reproduce v360's other habits (clamping float input
to [0, 1], filling the pixels its input projection does not see with the input's top-left pixel, the
integer face sizes it rounds non-divisible cube maps to): the output keeps HDR values, and alpha where
the source has no ray.
"""

from __future__ import annotations

from copy import copy
from dataclasses import replace

import numpy as np

from lenslab.errors import WarpError
from lenslab.lenses import Camera
from lenslab.warp.engine import WarpPlan
from lenslab.warp.maps import MapBand

READS = ("span", "span-halves", "centre", "shift")


def v360_read(lens) -> str:
    """How v360 reads ``lens`` as its input (see the module docstring); a WarpError if it has no
    counterpart in v360."""
    how = getattr(lens, "v360_read", None)
    if how not in READS:
        raise WarpError(f"--compat v360: ffmpeg's v360 has no projection matching {lens.spec()}; "
                        "see docs/v360.md for the projections both share")
    return how


def to_v360_index(xs: np.ndarray, ys: np.ndarray, valid: np.ndarray, lens, how: str) -> None:
    """Move lenslab's index coordinates (``p - 1/2``) to the ones v360 reads at, in place (float32)."""
    x, y = xs[valid], ys[valid]
    if how == "centre":
        return
    x += np.float32(0.5)  # back to lenslab's continuous coordinate p
    y += np.float32(0.5)
    if how != "shift":
        if how == "span-halves":
            half = lens.width / 2.0
            right = x >= half
            x -= np.where(right, np.float32(half), np.float32(0.0)).astype(np.float32)
            x *= np.float32((half - 1.0) / half)
            x += np.where(right, np.float32(half), np.float32(0.0)).astype(np.float32)
        else:
            x *= np.float32((lens.width - 1.0) / lens.width)
        y *= np.float32((lens.height - 1.0) / lens.height)
    xs[valid], ys[valid] = x, y


def check_v360(src_lens=None, dst_lens=None, samples: int = 1, antialias: bool = False) -> str | None:
    """What ``--compat v360`` needs, checked from the lenses and options alone (no file): one sample per
    pixel, a source that v360 reads and an output that v360 makes. Returns how v360 reads ``src_lens``
    (None without one); a WarpError says what v360 lacks."""
    if samples != 1 or antialias:
        raise WarpError("--compat v360 reproduces v360's one sample per pixel; drop --samples/--antialias")
    if dst_lens is not None and not getattr(dst_lens, "v360_output", False):  # v360's output-only projections
        v360_read(dst_lens)  # the output must be a v360 projection too
    return None if src_lens is None else v360_read(src_lens)


def v360_output(camera: Camera) -> Camera:
    """``camera`` with the rays v360 gives its output pixels (:mod:`lenslab.lenses.core.v360`): a copy of its lens
    whose ``pixel_to_dir`` is the lens's ``v360_pixel_to_dir``, where it has one (``camera`` itself otherwise)."""
    rays = getattr(camera.lens, "v360_pixel_to_dir", None)
    if rays is None:
        return camera
    lens = copy(camera.lens)
    lens.pixel_to_dir = rays  # the copy's own, ahead of its class's
    return Camera(lens, camera.pose)


class V360Plan(WarpPlan):
    """A :class:`WarpPlan` with v360's sample positions and the output pixels it fills (see the module docstring)."""

    def __init__(self, src_camera: Camera, dst_camera: Camera, **options):
        self.read = check_v360(src_camera.lens, dst_camera.lens, options.get("samples", 1),
                               options.get("antialias", False))
        super().__init__(src_camera, v360_output(dst_camera), **options)
        if self.channels is not None:
            raise WarpError("--compat v360: ffmpeg's v360 has no per-channel optics (chromatic aberration); "
                            "drop --compat v360 or the lens's tca")
        self.border = replace(self.border, pole_top=False, pole_bottom=False)  # v360 clamps rows at the poles

    def _band(self, r0: int, r1: int, out: tuple | None = None) -> MapBand:
        band = self.mapper.map_band(r0, r1, self._offsets(r0, r1), out)
        to_v360_index(band.xs, band.ys, band.valid, self.src.lens, self.read)
        return band


def v360_plan(src_camera: Camera, dst_camera: Camera, **options) -> V360Plan:
    """A plan mapping pixels as ffmpeg's v360 does; run it with ``plan.run(image)``."""
    return V360Plan(src_camera, dst_camera, **options)


__all__ = ["V360Plan", "check_v360", "v360_output", "v360_plan", "v360_read"]
