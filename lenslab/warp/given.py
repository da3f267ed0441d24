"""Warping by a map made elsewhere (scikit-image's ``warp`` shape): the engine takes any inverse map.

An ST map from a compositing tool, a map from OpenCV's ``initUndistortRectifyMap`` or one a user
computed: for every output pixel, the continuous source position it reads. :func:`warp_with_map`
samples the source there with lenslab's exact filters and, with ``antialias``, averages it over each
pixel's footprint (the map's differences between neighbouring pixels, as for a lens-to-lens warp).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Callable

import numpy as np
from numpy.typing import ArrayLike

from lenslab.errors import WarpError
from lenslab.filters import check_filter_with_antialias, filter_named
from lenslab.io.alpha import settle
from lenslab.warp.checks import drawn_into, finite_given, held_coverage
from lenslab.warp.kernels.dispatch import contiguous_rows, run_bands
from lenslab.warp.minification import watch
from lenslab.warp.filters import sample
from lenslab.warp.seam import Border, border_of

if TYPE_CHECKING:
    from lenslab.warp.antialias import FootprintBand
    from lenslab.lenses import Camera, Lens
    from lenslab.warp.minification import Looked

BAND_ROWS_POINTS = 1 << 18  # output pixels per band


def warp_with_map(image: ArrayLike, src_xy: ArrayLike, valid: ArrayLike | None = None, filter: str = "bilinear",
                  antialias: bool = False, source: Lens | Camera | None = None,
                  progress: Callable[[int], None] | None = None,
                  alpha_channel: bool | None = None, looked: Looked | None = None,
                  into: tuple | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Warp ``image`` by an inverse map: each output pixel reads the source where the map says.
    ``alpha_channel=False``: the image holds data channels only (the last of 2 or 4 is not settled as
    alpha; :func:`lenslab.io.carries_alpha`).

    Parameters
    ----------
    image : array_like
        ``H x W`` or ``H x W x C`` source values.
    src_xy : array_like
        ``(h, w, 2)`` source positions in lenslab's continuous pixel coordinates (x right, y down,
        origin at the image's top-left corner, pixel centres at +0.5), one per output pixel centre;
        any float dtype (computed in float64, stored as float32 index coordinates).
    valid : array_like, optional
        ``(h, w)`` bool, where the map has a source position; default: where ``src_xy`` is finite.
        Positions outside the source image read its edge (or beyond its seams, see ``source``).
    filter : str
        ``nearest``, ``bilinear``, ``bicubic`` or ``lanczos`` (:data:`lenslab.filters.FILTERS`).
    antialias : bool
        Average the source over each pixel's footprint (from the map's differences between
        neighbouring pixels) instead of one filtered tap; for maps that shrink the source. It replaces
        the filter, so ``filter`` stays ``"bilinear"`` with it (another is a WarpError).
    source : lenslab.lenses.Lens or lenslab.lenses.Camera, optional
        The source's lens, whose seams and pieces say how taps beyond its edges continue (a panorama's
        wrap and poles, a cube map's neighbouring faces); default: taps clamp to the edge pixel.
    progress : callable, optional
        Called with the number of output rows done.
    alpha_channel : bool, optional
        Whether the image's last channel is alpha: None decides by the channel count (2 or 4), False
        keeps every channel as data (none clipped to [0, 1] or used as coverage), True makes the last one
        alpha (an image of two channels or more).
    looked : lenslab.warp.minification.Looked, optional
        With ``antialias``: the footprints are looked at for it as they are drawn, and
        :func:`lenslab.warp.minification.shrinks` then says whether the map shrinks its source anywhere.
    into : tuple of numpy.ndarray, optional
        ``(image, alpha)`` float32 arrays of the output's shapes to draw into (the channels of one RGBA image,
        :func:`lenslab.io.alpha.room_for_alpha`); ``(image or None, None)``: no coverage kept, returned as None.

    Returns
    -------
    image : numpy.ndarray
        float32 ``h x w x C`` (``h x w`` for a 2-D input), 0 where invalid; a source's NaN read as 0 and its
        +-inf as the largest float32 (:func:`lenslab.warp.checks.finite_given`, a RuntimeWarning says so).
    alpha : numpy.ndarray
        float32 ``h x w``: 1 where valid, 0 elsewhere.

    Examples
    --------
    A map that reads each output pixel one pixel to the right of where it sits:

    >>> import numpy as np
    >>> from lenslab.warp import warp_with_map
    >>> src = np.arange(12, dtype=np.float32).reshape(3, 4)
    >>> y, x = np.mgrid[0:3, 0:3] + 0.5
    >>> out, alpha = warp_with_map(src, np.stack([x + 1, y], axis=-1))
    >>> out.tolist()
    [[1.0, 2.0, 3.0], [5.0, 6.0, 7.0], [9.0, 10.0, 11.0]]
    """
    filter = filter_named(filter)
    check_filter_with_antialias(filter, antialias)
    from lenslab.errors import check_image_shape

    img = check_image_shape(image, channels=None)
    src = finite_given(np.ascontiguousarray(img[..., None] if img.ndim == 2 else img, dtype=np.float32))
    xy = np.asarray(src_xy)
    if xy.ndim != 3 or xy.shape[2] != 2:
        raise WarpError(f"the map must have shape (h, w, 2) (a source x, y per output pixel), got {xy.shape}")
    h, w = xy.shape[:2]
    with np.errstate(invalid="ignore", over="ignore"):
        xs = xy[..., 0].astype(np.float32) - np.float32(0.5)
        ys = xy[..., 1].astype(np.float32) - np.float32(0.5)
    ok = np.isfinite(xs) & np.isfinite(ys)
    if valid is not None:
        valid = np.asarray(valid, dtype=bool)
        if valid.shape != (h, w):
            raise WarpError(f"valid must have the map's shape {(h, w)}, got {valid.shape}")
        ok &= valid
    xs[~ok] = 0.0
    ys[~ok] = 0.0
    border = Border() if source is None else border_of(getattr(source, "lens", source))
    from lenslab.warp import antialias as aa  # (loaded by the warps that antialias)

    pyr = aa.pyramid(src, border) if antialias else None

    def draw(r0, r1, o, a):
        if antialias:
            band = footprint_of_map(xs, ys, ok, r0, r1, float(src.shape[1]) if border.wrap else 0.0)
            if looked is not None:
                watch(looked, band)
            aa.sample_footprint(pyr, band, border, o, a)
        else:
            sample(src, xs[r0:r1, :, None], ys[r0:r1, :, None], ok[r0:r1, :, None], border, filter, o, a)

    out, alpha = draw_rows(src, (h, w), draw, progress, alpha_channel, into, drawn_over=not antialias)
    return (out[..., 0] if img.ndim == 2 else out), alpha


def draw_rows(src: np.ndarray, shape: tuple[int, int], draw, progress=None, alpha_channel: bool | None = None,
              into: tuple | None = None, drawn_over: bool = True, per_pixel: int = 1,
              points: int = BAND_ROWS_POINTS) -> tuple[np.ndarray, np.ndarray | None]:
    """The output (float32 h x W x C, the source's C) and coverage of a warp by a given map, drawn in bands of rows
    on the engine's threads by ``draw(r0, r1, out_rows, alpha_rows)`` (C-contiguous arrays of those rows) and
    settled (:func:`lenslab.io.alpha.settle`). ``into``: arrays to draw into, as
    :meth:`lenslab.warp.WarpPlan.run` takes them (the channels of one RGBA image; ``(image or None, None)``: no
    coverage kept, returned as None); ``drawn_over``: ``draw`` sets every pixel of its rows; ``per_pixel``: the
    samples it takes per pixel (a band holds about ``points`` of them)."""
    h, w = shape
    out, alpha = drawn_into(into, (h, w, src.shape[2]), drawn_over, drawn_over)
    rows = max(1, points // max(1, w * per_pixel))

    def band(rows_):
        with contiguous_rows(out[rows_[0]:rows_[1]], alpha[rows_[0]:rows_[1]], drawn_over=drawn_over) as (o, a):
            draw(*rows_, o, a)
        return rows_

    done = None if progress is None else (lambda rows_: progress(rows_[1] - rows_[0]))
    run_bands([(r, min(h, r + rows)) for r in range(0, h, rows)], band, done)
    settle(out, held_coverage(alpha), alpha_channel)
    return out, alpha if into is None or into[1] is not None else None


def footprint_of_map(xs, ys, ok, r0: int, r1: int, wrap: float) -> FootprintBand:
    """The footprint band of rows ``r0:r1`` of a given map (index coordinates, (h, w) float32; ``wrap``
    the source's period in x, 0 for none): sides
    from the differences between neighbouring pixels; no pixel is split at the edge of the valid
    region (there is no lens to map its sub-samples), so coverage there is 0 or 1."""
    from lenslab.warp import antialias as aa

    h, w = r1 - r0, xs.shape[1]
    foot = np.empty((h, w, 1, 4), dtype=np.float32)
    edge = np.empty((h, w, 1), dtype=np.bool_)
    aa.neighbour_secants(xs, ys, ok, r0, wrap, None, foot, edge)
    none = np.zeros(0, dtype=np.int64)
    return aa.FootprintBand(r0, r1, xs[r0:r1, :, None], ys[r0:r1, :, None], ok[r0:r1, :, None], foot,
                            np.zeros((h, w, 1), dtype=np.bool_), none, np.zeros((0, 1), np.float32),
                            np.zeros((0, 1), np.float32), np.zeros((0, 1), bool))
