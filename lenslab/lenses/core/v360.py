"""The rays ffmpeg's v360 gives the pixels of an output frame, where they differ from the lens's own.

v360 (with its default ``alpha_mask=0``) writes every output pixel: outside a fisheye's circle, a Hammer
ellipse or the sine curves of a sinusoidal frame, and in the padding of an equi-angular cube map, it
carries its formulas on (a fisheye past its field of view, an equidistant one past the back pole); where
its formula has no answer it reports the pixel invisible and still samples a fixed direction (down for
``ball`` and ``perspective``, forward for ``og`` past 90 degrees); an equisolid frame past the back
pole is its one place with no sample at all (zeros). A lens whose frame has such parts says so with a
``v360_pixel_to_dir(xy)`` method, built from the helpers here; ``lenslab warp --compat v360`` uses it
for the output (:mod:`lenslab.warp.compat_v360`).

As its input, v360 reads a direction a projection does not see from the input's top-left pixel (a ``flat``,
fisheye, ``cylindrical`` or ``pannini`` input: the lens's ``v360_unseen`` is :data:`TOP_LEFT`), and some
inputs see more than the lens does (a fisheye's whole frame, corners included; ``mercator`` and ``hequirect``
clamped to their edge rows and columns): such a lens gives where v360 reads as ``v360_dir_to_pixel(d)``.
"""

from __future__ import annotations

import numpy as np

from lenslab.lenses.core.base import as_points, clean

#: the direction v360 samples at ``ball`` and ``perspective`` pixels it reports invisible: its +y, down
DOWN = (0.0, -1.0, 0.0)
#: the direction v360 samples at ``og`` pixels past 90 degrees from the axis, which it reports invisible
FORWARD = (0.0, 0.0, 1.0)


def filled(lens, xy: np.ndarray, d: np.ndarray, ok: np.ndarray, fill=None) -> tuple[np.ndarray, np.ndarray]:
    """``(d, ok)`` of pixels ``xy`` (float64 ``(..., 2)``) kept to the image's finite pixels, with ``fill`` (a
    camera-space direction, or None) at those where ``ok`` is False; zeros where there is no ray."""
    with np.errstate(over="ignore", invalid="ignore"):
        inside = lens.in_image(xy) & np.isfinite(np.einsum("...i,...i->...", xy, xy))
    if fill is None:
        return clean(d, ok & inside, inplace=True)
    np.copyto(d, np.asarray(fill, dtype=np.float64), where=(inside & ~ok)[..., None])
    return clean(d, inside, inplace=True)


def continued(lens, xy, uv_to_dir, fill=None) -> tuple[np.ndarray, np.ndarray]:
    """``(d, ok)`` of pixels ``xy`` through the lens's ``pixel_to_uv`` and ``uv_to_dir(uv) -> (d, ok)`` (its formulas
    carried on past the lens's own edge, ``ok`` where v360 has a ray), ``fill`` where it has none (see :func:`filled`)."""
    xy = as_points(xy, 2, "pixel coordinates")
    with np.errstate(all="ignore"):
        d, ok = uv_to_dir(lens.pixel_to_uv(xy))
    return filled(lens, xy, d, np.asarray(ok, dtype=bool) & np.ones(d.shape[:-1], dtype=bool), fill)


#: a source lens's ``v360_unseen``: v360 reads the input's top-left pixel for a direction it does not see
TOP_LEFT = "top-left"


__all__ = ["DOWN", "FORWARD", "TOP_LEFT", "continued", "filled"]
