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
with lenslab's lens models and filters, and reads as v360 does where the source lens has no ray
(``v360_dir_to_pixel``: a fisheye's frame corners, clamped edges; ``v360_unseen``: the top-left pixel). It
does not reproduce v360's other habits (clamping float input to [0, 1], the integer face sizes it rounds
non-divisible cube maps to): the output keeps HDR values.
"""

from __future__ import annotations

from copy import copy
from dataclasses import replace

import numpy as np

from lenslab.errors import WarpError
from lenslab.lenses import Camera
from lenslab.warp.engine import WarpPlan
from lenslab.warp.maps import MapBand, exact_map_parts

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
        offsets = self._offsets(r0, r1)
        band = self.mapper.map_band(r0, r1, offsets, out)
        to_v360_index(band.xs, band.ys, band.valid, self.src.lens, self.read)
        if not band.valid.all():
            self._read_unseen(band, offsets)
        return band

    def _read_unseen(self, band: MapBand, offsets: np.ndarray) -> None:
        """Where v360 reads the samples whose output ray the source lens does not see (an output ray that v360
        itself has): where the lens's ``v360_dir_to_pixel`` says v360 still sees it (clamped to the frame, as v360
        clamps its taps), else the top-left pixel for a lens whose ``v360_unseen`` says so."""
        lens = self.src.lens
        further = getattr(lens, "v360_dir_to_pixel", None)
        top_left = getattr(lens, "v360_unseen", None) == "top-left"
        if further is None and not top_left:
            return
        r, c, k = np.nonzero(~band.valid)
        o = np.asarray(offsets, np.float64).reshape(-1, 2)[k]  # one sample per pixel, the same offsets in each
        pts = np.stack([c + o[:, 0], band.r0 + r + o[:, 1]], axis=-1)
        _, _, ray, d = exact_map_parts(self.src, self.dst, pts, with_dirs=True)
        xs, ys = np.zeros(len(r), np.float32), np.zeros(len(r), np.float32)
        seen = np.zeros(len(r), bool)
        if further is not None:
            px, seen = further(d)
            seen &= ray
            xs[:], ys[:] = px[:, 0] - 0.5, px[:, 1] - 0.5
            to_v360_index(xs, ys, seen, lens, self.read)
            np.clip(xs, 0.0, lens.width - 1.0, out=xs)
            np.clip(ys, 0.0, lens.height - 1.0, out=ys)
        fill = seen | (ray & top_left)
        xs[~seen], ys[~seen] = 0.0, 0.0  # the top-left pixel's centre, in v360's reading as in lenslab's
        at = (r[fill], c[fill], k[fill])
        band.xs[at], band.ys[at], band.valid[at] = xs[fill], ys[fill], True


def v360_plan(src_camera: Camera, dst_camera: Camera, **options) -> V360Plan:
    """A plan mapping pixels as ffmpeg's v360 does; run it with ``plan.run(image)``."""
    return V360Plan(src_camera, dst_camera, **options)


__all__ = ["V360Plan", "check_v360", "v360_output", "v360_plan", "v360_read"]
