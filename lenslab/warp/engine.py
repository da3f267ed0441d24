"""The warp itself: a plan (cameras, filter, sampling) run band by band over the output.

Memory stays bounded whatever the sizes: the output is produced in bands of rows, each needing only its own map
(``band_points`` samples at a time, 9 bytes each, plus the float64 working set of the lens models for the samples
computed exactly), so a warp needs the source, the output and a fixed working set per thread (bands run one per
thread, :func:`lenslab.warp.kernels.dispatch.threads` of them at once), plus the map lattice (five float64 per 8 x
8 output pixels). Measured by ``lenslab bench warp --big``, one thread: a 16384x8192 float RGB source (1.5 GiB)
into an 8192x8192 180-degree view (0.75 GiB + 0.25 GiB alpha) allocates about 50 MiB beyond the output.
``antialias=True`` adds the source's mip pyramid (a third of the source) and 16 bytes of footprint per output pixel
of a band. A plan made with ``cache=True`` keeps every band's map (for many images of the same geometry, see
:mod:`lenslab.warp.batch`); a one-sample bilinear map is kept as taps, a source offset and two weights per pixel
(:mod:`lenslab.warp.taps`).
"""

from __future__ import annotations

import warnings
from typing import Callable

import numpy as np
from numpy.typing import ArrayLike

from lenslab.errors import WarpError
from lenslab.filters import check_filter_with_antialias, filter_named
from lenslab.io.alpha import colour_channels
from lenslab.lenses import Camera
from lenslab.warp.kernels.dispatch import contiguous_rows, run_bands, scratch, threads
from lenslab.warp.checks import (EmptyViewWarning, OutputChecks, checked_source, drawn_into,  # noqa: F401
                                 finite_output, held_coverage, settle_checked)
from lenslab.warp.filters import all_finite, sample
from lenslab.warp.maps import MapBand, Mapper, check_eyes, sample_pattern
from lenslab.warp.eyes import crop_source, eye_pairs
from lenslab.warp.optics import channel_cameras, divide_by_falloff, falloff_image, render_channels
from lenslab.warp.seam import border_of
from lenslab.warp.taps import TapBand, eligible, sample_taps, source_spans, source_window, taps_of
from lenslab.warp.tiles import has_camera_pieces, render_region, tile_cameras
from lenslab.warp.views import ViewBand, has_views, sample_views, view_band


def _aa():  # the footprint prefilter (lenslab.warp.antialias), loaded by the first plan that antialiases
    from lenslab.warp import antialias
    return antialias


BAND_POINTS = 1 << 18  # output samples per band

#: strata per pixel (4 x 4) when ``antialias`` meets a source that blends several views (dual fisheye)
VIEW_AA_SAMPLES = 16

class WarpPlan:
    """Everything about a warp except the pixels: reusable for many images of one geometry.

    See :func:`lenslab.warp.warp` for the parameters. With ``cache=True`` the maps are computed
    once, on first use, and kept (``map_bytes`` tells how much memory they take).
    """

    def __init__(self, src_camera: Camera, dst_camera: Camera, filter: str = "bilinear", samples: int = 1,
                 antialias: bool = False, seed: int | None = None, allow_parallax: bool = False,
                 exact_map: bool = False, cache: bool = False, band_points: int = BAND_POINTS, optics: bool = True):
        for name, cam in (("source", src_camera), ("destination", dst_camera)):
            if not isinstance(cam, Camera):
                raise WarpError(f"the {name} camera must be a lenslab Camera, got {type(cam).__name__}; "
                                "build one with Camera.from_spec(spec, (width, height))")
        filter = filter_named(filter)
        check_filter_with_antialias(filter, antialias)
        try:
            samples = int(samples)
        except (TypeError, ValueError):
            raise WarpError(f"samples must be a whole number of samples per pixel, got {samples!r}") from None
        if not 1 <= samples <= 1024:
            raise WarpError(f"samples per pixel must be in 1..1024, got {samples}")
        self.src, self.dst = src_camera, dst_camera
        self.filter, self.samples, self.antialias = filter, samples, bool(antialias)
        self.seed, self.cache = seed, bool(cache)
        self.band_points = max(1, int(band_points))
        self._bands: list | None = None
        self.border = border_of(src_camera.lens)
        self.parts = self.channels = None
        self.views = False
        opts = dict(filter=filter, samples=samples, antialias=antialias, seed=seed,
                    allow_parallax=allow_parallax, exact_map=exact_map, cache=cache, band_points=band_points)
        eyes = eye_pairs(src_camera, dst_camera)
        if eyes is not None:
            # stereo frames (lenslab.warp.eyes): one plan per output eye, each reading its source eye
            self.parts = [(x0, y0, type(self)(s_cam, d_cam, **opts), crop) for x0, y0, crop, s_cam, d_cam in eyes]
            self.parallax = max(p.parallax for _, _, p, _ in self.parts)
            self.mapper = None
            return
        if has_camera_pieces(dst_camera):
            # one plan per tile: each tile's map is smooth (and interpolated) on its own
            self.parts = [(x0, y0, WarpPlan(src_camera, cam, **opts), None)
                          for x0, y0, cam in tile_cameras(dst_camera) if cam is not None]
            self.parallax = max([p.parallax for _, _, p, _ in self.parts], default=0.0)
            self.mapper = None
            return
        # per-channel lenses and falloffs (lenslab.warp.optics); the channel plans leave them to this one
        self.src_falloff = self.dst_falloff = None
        if optics:
            self.src_falloff, self.dst_falloff = falloff_image(src_camera.lens), falloff_image(dst_camera.lens)
            pairs = channel_cameras(src_camera, dst_camera)
            if pairs is not None:
                opts = dict(filter=filter, samples=samples, antialias=antialias, seed=seed,
                            allow_parallax=allow_parallax, exact_map=exact_map, cache=cache,
                            band_points=band_points, optics=False)
                self.channels = [WarpPlan(s, d, **opts) for s, d in pairs]
                self.parallax = max(p.parallax for p in self.channels)
                self.mapper = None
                return
        self.parallax = check_eyes(src_camera, dst_camera, allow_parallax)
        self.mapper = Mapper(src_camera, dst_camera, exact=exact_map)
        # a source that sees some directions twice blends its views (lenslab.warp.views)
        self.views = has_views(src_camera.lens)
        if self.views and self.antialias:
            # the footprint prefilter reads one place per direction: a many-view source is antialiased by
            # supersampling its blended views instead, at least VIEW_AA_SAMPLES strata per pixel
            self.antialias = False
            self.samples = max(self.samples, VIEW_AA_SAMPLES)

    # -- geometry ------------------------------------------------------------------------------
    @property
    def out_shape(self) -> tuple[int, int]:
        return self.dst.height, self.dst.width

    def band_rows(self) -> list[tuple[int, int]]:
        w, h = self.dst.size
        per = self.samples * (_aa().JACOBIAN_POINTS if self.antialias and self.samples > 1 else 1)
        rows = max(1, self.band_points // max(1, w * per))
        rows = min(rows, -(-h // threads()))  # at least one band per thread
        return [(r, min(h, r + rows)) for r in range(0, h, rows)]

    def _offsets(self, r0: int, r1: int) -> np.ndarray:
        if self.seed is None or self.samples == 1:
            return sample_pattern(self.samples)
        return self.dst.pixel_grid(slice(r0, r1), self.samples, self.seed) - np.concatenate(
            [np.broadcast_to(np.arange(self.dst.width, dtype=np.float64)[None, :, None, None],
                             (r1 - r0, self.dst.width, self.samples, 1)),
             np.broadcast_to(np.arange(r0, r1, dtype=np.float64)[:, None, None, None],
                             (r1 - r0, self.dst.width, self.samples, 1))], axis=-1)

    def _band(self, r0: int, r1: int, out: tuple | None = None):
        """The map of rows ``r0:r1``; a plain map into ``out`` = (xs, ys, valid) when given (Mapper.map_band)."""
        if self.views:
            return view_band(self.mapper, r0, r1, self._offsets(r0, r1))
        if self.antialias:
            return _aa().footprint_band(self.mapper, r0, r1, self._offsets(r0, r1))
        return self.mapper.map_band(r0, r1, self._offsets(r0, r1), out)

    def _kept_band(self, r0: int, r1: int):
        """A band's map as a cached plan keeps it: as taps where it can (:mod:`lenslab.warp.taps`)."""
        band = self._band(r0, r1)
        if (not self.views and not self.antialias and isinstance(band, MapBand)
                and eligible(self.filter, self.samples, self.border, self.src.width * self.src.height)):
            return taps_of(band, self.src.width, self.src.height)
        return band

    def bands(self):
        """The map of every band, computed now (and kept when the plan caches; a plan that has kept its
        bands as taps computes the maps again)."""
        if self._bands is not None and not any(isinstance(b, TapBand) for b in self._bands):
            yield from self._bands
            return
        kept = [] if self.cache and self._bands is None else None
        for r0, r1 in self.band_rows():
            band = self._band(r0, r1)
            if kept is not None:
                kept.append(band)
            yield band
        if kept is not None:
            self._bands = kept

    def prepare(self) -> None:
        """Compute and keep the maps now, where the plan caches them (as its first image would), its pieces' too."""
        for part in [p for _, _, p, _ in self.parts or ()] + list(self.channels or ()):
            part.prepare()
        if self.cache and self._bands is None and self.parts is None and self.channels is None:
            self._bands = run_bands(self.band_rows(), lambda rows: self._kept_band(*rows))

    def source_window(self) -> tuple[int, int, int, int] | None:
        """``(row0, row1, col0, col1)``: the box around :meth:`source_spans`, or None when they are not known."""
        return None if (spans := self.source_spans()) is None else source_window(spans)

    def source_spans(self) -> np.ndarray | None:
        """The source pixels this plan reads, row by row (:func:`lenslab.warp.taps.source_spans`), once its maps are
        kept as taps (after the first image), else None. A video decoder converts only these pixels of each frame."""
        bands = self._bands
        if self.parts is not None or self.channels is not None or not bands or \
                not all(isinstance(b, TapBand) for b in bands):
            return None
        if getattr(self, "_spans", None) is None:
            self._spans = source_spans(bands, self.border, self.src.width, self.src.height)
        return self._spans

    @property
    def map_bytes(self) -> int:
        if self.parts is not None:
            return sum(p.map_bytes for _, _, p, _ in self.parts)
        if self.channels is not None:
            return sum(p.map_bytes for p in self.channels)
        return 0 if self._bands is None else sum(b.nbytes for b in self._bands)

    # -- pixels --------------------------------------------------------------------------------
    def check_image(self, image) -> np.ndarray:
        """The image as the float32 H x W x C source of this plan (WarpError for another size or type)."""
        return checked_source(image, self.src)

    def run(self, image, progress: Callable[[int], None] | None = None, into=None,
            alpha_channel: bool | None = None, on_band: Callable | None = None):
        """Warp one image: ``(image float32 H x W x C, alpha float32 H x W)`` of the destination size.

        ``into``: ``(image, alpha)`` arrays of those shapes to write into, drawn over (zeroed first where the bands
        may leave pixels, :meth:`_draws_every_pixel`; a clip's frames reuse a few); new arrays when they do not fit;
        ``(image or None, None)``: no coverage kept (returned as None; :func:`~lenslab.warp.checks.drawn_into`).
        ``alpha_channel=False``: the image holds data channels only (none settled as alpha). ``on_band(rows,
        sl)``: called with the output's final rows ``sl`` (``rows`` = ``image[sl]``) as each band is drawn, on its
        thread while they are in cache (a clip's encoder takes them there), or once with every row after a
        warp whose pixels changed after its bands (alpha settled, values made finite, a falloff, pieces)."""
        src = self.check_image(image)
        h, w = self.out_shape
        whole = self._draws_every_pixel()
        out, alpha = drawn_into(into, (h, w, src.shape[2]), whole, whole and self.dst_falloff is None)
        kept = into is None or into[1] is not None
        # zeros to begin with (filled, or new pages) and a plane of coverage a pixel: samples without a source left alone
        zeroed = (not whole or out is not (into[0] if into is not None else None)) and alpha.strides[0] != 0
        checks = OutputChecks.of(src.shape[2], alpha_channel, on_band)  # made by the bands when they draw it all
        drawn = self.render(src, out, alpha, progress, checks, alpha_channel, zeroed)
        covered = checks.covered if drawn else None  # (every band seen: whether any pixel is covered)
        if not (checks.finite if drawn else all_finite(out)):
            warnings.warn(finite_output(self.render, src, out, alpha, alpha_channel), RuntimeWarning, stacklevel=2)
            drawn = False  # drawn again or clamped: the bands' checks no longer hold
        settle_checked(out, held_coverage(alpha), alpha_channel, checks if drawn else None, covered)
        if on_band is not None and not (drawn and checks.in_range):  # changed after the bands gave their rows
            on_band(out, slice(0, h))
        if np.ndim(image) == 2:
            out = out[..., 0]
        return out, alpha if kept else None

    def _draws_every_pixel(self) -> bool:
        """Whether rendering sets every output pixel (a plain map's bands: taps and :func:`sample`): no zeroing first."""
        return self.parts is None and self.channels is None and not self.views and not self.antialias

    def render(self, src: np.ndarray, out: np.ndarray, alpha: np.ndarray,
               progress: Callable[[int], None] | None = None, checks: OutputChecks | None = None,
               alpha_channel: bool | None = None, zeroed: bool = False) -> bool:
        """Warp the checked float32 H x W x C source into ``out``/``alpha`` (views of the output size);
        ``alpha_channel``: whether the image carries alpha (:func:`lenslab.io.alpha.alpha_last`). True when
        this plan's bands drew the whole output as it stands and gave each band to ``checks``."""
        if self.parts is not None:
            for x0, y0, part, crop in self.parts:
                render_region(part, crop_source(src, crop), out, alpha, x0, y0, progress, alpha_channel)
            return False
        if self.src_falloff is not None:  # light, not coverage: alpha is left alone
            src = divide_by_falloff(src, self.src_falloff, alpha_channel)
        if self.dst_falloff is not None:
            checks = None  # the falloff changes the output after the bands
        if self.channels is not None:
            render_channels(self.channels, src, out, alpha, progress)
            checks = None
        else:
            self._render_bands(src, out, alpha, progress, checks, zeroed)
        if self.dst_falloff is not None:
            out[..., colour_channels(out.shape[2], alpha_channel)] *= self.dst_falloff[..., None]
        return checks is not None

    def _render_bands(self, src: np.ndarray, out: np.ndarray, alpha: np.ndarray, progress,
                      checks: OutputChecks | None = None, zeroed: bool = False) -> None:
        aa = _aa() if self.antialias else None
        pyramid = aa.pyramid(src, self.border, lazy=True) if aa else None
        whole = self._draws_every_pixel()  # (a strided output's band: drawn in scratch, given its rows unless whole)

        def draw(band):
            sl, said = slice(band.r0, band.r1), None  # said: what the sampler says of its rows (None: scan them)
            with contiguous_rows(rows := out[sl], alpha[sl], drawn_over=whole) as (o, a):
                if isinstance(band, TapBand):
                    sample_taps(src, band, self.border, o, a)
                elif isinstance(band, ViewBand):
                    sample_views(src, band, self.border, self.filter, o, a)
                elif self.antialias:
                    aa.draw_footprints(self, pyramid, band, o, a)
                else:
                    said = sample(src, band.xs, band.ys, band.valid, self.border, self.filter, o, a,
                                  zeroed=zeroed and o is rows)
                if checks is not None:
                    checks.band(o, a, sl, said)
            return band

        done = None if progress is None else (lambda band: progress(band.r1 - band.r0))

        if self._bands is not None:
            run_bands(self._bands, draw, done)
            return
        # one band per thread, map and pixels; a band's map is dropped once drawn unless the plan caches
        if self.cache:
            self._bands = run_bands(self.band_rows(), lambda rows: draw(self._kept_band(*rows)), done)
        else:
            run_bands(self.band_rows(), lambda rows: self._drawn(*rows, draw), done)

    def _drawn(self, r0: int, r1: int, draw) -> "_Rows":
        """Map and draw rows ``r0:r1`` without caching: a plain map in scratch arrays reused band to band."""
        if self.views or self.antialias:
            return _Rows(draw(self._band(r0, r1)))
        shape = (r1 - r0, self.dst.width, self.samples)
        with scratch(shape, np.float32) as xs, scratch(shape, np.float32) as ys, scratch(shape, np.bool_) as ok:
            return _Rows(draw(self._band(r0, r1, (xs, ys, ok))))


class _Rows:
    """The rows a band covered, without its map (what a plan that does not cache keeps of a band)."""
    __slots__ = ("r0", "r1")
    def __init__(self, band):
        self.r0, self.r1 = band.r0, band.r1


def warp(image: ArrayLike, src_camera: Camera, dst_camera: Camera, filter: str = "bilinear", samples: int = 1,
         antialias: bool = False, seed: int | None = None, allow_parallax: bool = False,
         exact_map: bool = False, band_points: int = BAND_POINTS, progress: Callable[[int], None] | None = None,
         alpha_channel: bool | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Reproject ``image`` seen by ``src_camera`` into the view of ``dst_camera``.

    Each output pixel takes ``samples`` stratified sub-pixel samples; a sample is *valid* when its
    output ray exists (e.g. inside a circular image's circle) and the source lens sees that direction
    inside its image. A source wraps at its seams, continues across its poles and reads across its
    pieces' edges as its lens says (:mod:`lenslab.warp.seam`). Values are never clamped (HDR in, HDR
    out), the work is float32 in, float32 out (weights and maps in float64) and NaN is never produced.

    Parameters
    ----------
    image : array_like
        ``H x W x C`` or ``H x W`` values of the source camera's size, any number of channels.
    src_camera, dst_camera : lenslab.lenses.Camera
        The camera that saw ``image`` and the one to see it through. Their eyes must be one point (a
        panorama holds one eye).
    filter : str
        ``nearest``, ``bilinear``, ``bicubic`` (Catmull-Rom) or ``lanczos`` (Lanczos-3), or another name of
        one (:data:`lenslab.filters.FILTERS`).
    samples : int
        Sub-pixel samples per output pixel (strata centres, or jittered per row with ``seed``).
    antialias : bool
        Prefilter by each pixel's footprint on the source (:mod:`lenslab.warp.antialias`), for outputs
        that shrink the source; combines with ``samples``. It replaces the filter (it averages the
        bilinear source), so ``filter`` stays ``"bilinear"`` with it.
    seed : int, optional
        Jitter the sub-pixel samples, deterministically per row.
    allow_parallax : bool
        Eyes that differ: warn (:class:`~lenslab.warp.maps.ParallaxWarning`) and take every ray from the
        source's eye, instead of raising.
    exact_map : bool
        Evaluate the lens models at every sample instead of interpolating a checked lattice
        (:mod:`lenslab.warp.maps`).
    band_points : int
        Samples mapped at a time (bounds the working memory).
    progress : callable, optional
        Called with the number of output rows done.
    alpha_channel : bool, optional
        Whether the image's last channel is alpha: True for ``... A``, False for data channels only
        (``u, v``; ``R, G, B, Z``), as :func:`lenslab.io.carries_alpha` says from a file's channel names.
        None: an image of 2 or 4 channels carries alpha (:func:`lenslab.io.alpha.alpha_last`).

    Returns
    -------
    image : numpy.ndarray
        float32 ``h x w x C`` (``h x w`` for a 2-D input) of the destination camera's size, the colour
        *premultiplied* by ``alpha`` (the OpenEXR convention): the sum of the valid samples divided by
        the number of samples. Divide by alpha where alpha > 0 for straight colour.
    alpha : numpy.ndarray
        float32 ``h x w`` coverage: the fraction of each pixel's samples that are valid, exactly 0 where
        none is. An image that carries alpha (``alpha_channel``) has it last (premultiplied); it is warped
        like colour (so it includes the coverage). Every alpha ends in [0, 1]
        (:func:`lenslab.io.alpha.settle`); vignetting and its removal change colour, never alpha.
        ``lenslab.write(path, image, alpha=alpha)`` stores both as RGBA.

    Raises
    ------
    lenslab.errors.WarpError
        An image of the wrong size or with NaN or infinite values, an unknown filter, a filter other
        than bilinear with ``antialias``, or eyes that differ without ``allow_parallax``.

    Examples
    --------
    A uniform panorama of radiance 2 seen through a 180-degree fisheye: 2 inside the image circle,
    transparent outside it.

    >>> import numpy as np, lenslab
    >>> from lenslab.lenses.projections.equirect import Equirect
    >>> from lenslab.lenses.projections.fisheye import Fisheye
    >>> pano = np.full((64, 128, 3), 2.0, np.float32)
    >>> src = lenslab.Camera(Equirect(128, 64))
    >>> dst = lenslab.Camera(Fisheye(32, 32, fov=180))
    >>> image, alpha = lenslab.warp(pano, src, dst)
    >>> image.shape, alpha.shape, image.dtype
    ((32, 32, 3), (32, 32), dtype('float32'))
    >>> float(image[16, 16, 0]), float(alpha[16, 16]), float(alpha[0, 0])
    (2.0, 1.0, 0.0)
    """
    plan = WarpPlan(src_camera, dst_camera, filter=filter, samples=samples, antialias=antialias, seed=seed,
                    allow_parallax=allow_parallax, exact_map=exact_map, band_points=band_points)
    return plan.run(image, progress=progress, alpha_channel=alpha_channel)


__all__ = ["WarpPlan", "warp", "MapBand", "EmptyViewWarning"]
