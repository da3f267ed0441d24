"""ST maps: lens-to-lens inverse maps for compositors, in Nuke's STMap convention.

An ST map is an image the size of the output whose pixel ``(i, j)`` holds where the output pixel's
centre reads the source, as fractions of the source's size::

    R = s = x_src / W_src          G = t = 1 - y_src / H_src          A = 1 where there is a ray, else 0

with ``(x_src, y_src)`` in lenslab's continuous pixel coordinates (the centre of source pixel ``(k, l)``
at ``(k + 1/2, l + 1/2)``), so ``s = (k + 1/2) / W`` at a pixel centre and ``t`` grows upward, as Nuke's
STMap node reads them. Maps are written as 32-bit float EXR (half floats would move a 4096-pixel source
by up to a pixel); B is 0. A map from lens A to lens B (``--from A --to B``) puts an image shot with A
into B: from a distorted lens to an ideal one it undistorts, the other way round it distorts.

Reading accepts maps made by any tool: float EXR (or any float format lenslab reads) with s and
t in the first two channels and, if present, validity in the fourth (``A > 1/2``); without alpha every
pixel whose ``s, t`` is finite and inside ``[0, 1]`` counts.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable

import numpy as np

from lenslab.errors import WarpError

if TYPE_CHECKING:
    from lenslab.lenses import Camera
    from lenslab.warp.minification import Looked

#: a link between neighbouring map entries is a jump (a seam, a face edge), never interpolated across,
#: when it is longer than JUMP_RATIO times the shorter of the links beside it plus JUMP_SLACK source px
JUMP_RATIO = 4.0
JUMP_SLACK = 1.0


def st_map(src: Camera, dst: Camera, progress: Callable[[int], None] | None = None,
           band_rows: int = 64) -> np.ndarray:
    """The ST map of the warp from camera ``src`` into camera ``dst``.

    Exact: the lens models are evaluated in float64 at every output pixel centre. Stereo frames pair
    their eyes as the warp does (:mod:`lenslab.warp.eyes`): each output eye reads its own source eye.

    Parameters
    ----------
    src, dst : lenslab.lenses.Camera
        The camera the source image was taken with and the one to make.
    progress : callable, optional
        Called with the number of output rows done, band after band.
    band_rows : int
        Output rows worked out at once (bounds the memory of the float64 rays).

    Returns
    -------
    numpy.ndarray
        float32 ``H x W x 4`` of ``dst``'s size: ``s``, ``t``, 0 and ``A`` (1 where the output pixel's
        ray lands on the source, else 0 with ``s = t = 0``).

    Examples
    --------
    From a camera to itself, each pixel reads its own centre: ``s = (k + 1/2) / W`` and
    ``t = 1 - (l + 1/2) / H`` (t grows upward, as Nuke reads it):

    >>> from lenslab import Camera
    >>> from lenslab.stmap import st_map
    >>> cam = Camera.from_spec("equirect", (8, 4))
    >>> st = st_map(cam, cam)
    >>> st.shape, st[0, 0].tolist()
    ((4, 8, 4), [0.0625, 0.875, 0.0, 1.0])

    A fisheye's corners lie outside its image circle: no ray, ``A = 0``:

    >>> fish = Camera.from_spec("fisheye:fov=180", (16, 16))
    >>> st = st_map(cam, fish)
    >>> float(st[0, 0, 3]), float(st[8, 8, 3])
    (0.0, 1.0)
    """
    from lenslab.warp.eyes import eye_pairs
    from lenslab.warp.maps import exact_map

    w, h = dst.size
    sw, sh = src.size
    out = np.zeros((h, w, 4), dtype=np.float32)
    for x0, y0, crop, s_cam, d_cam in eye_pairs(src, dst) or [(0, 0, None, src, dst)]:
        ox, oy = (crop[0], crop[1]) if crop else (0, 0)
        ew, eh = d_cam.size
        xs = np.arange(ew, dtype=np.float64) + 0.5
        for r0 in range(0, eh, band_rows):
            r1 = min(eh, r0 + band_rows)
            pts = np.stack(np.meshgrid(xs, np.arange(r0, r1, dtype=np.float64) + 0.5), axis=-1)
            xy, ok = exact_map(s_cam, d_cam, pts)
            band = out[y0 + r0:y0 + r1, x0:x0 + ew]
            band[..., 0] = np.where(ok, (xy[..., 0] + ox) / sw, 0.0)
            band[..., 1] = np.where(ok, 1.0 - (xy[..., 1] + oy) / sh, 0.0)
            band[..., 3] = ok
            if progress is not None:
                progress(r1 - r0 if ew == w else (r1 - r0) * ew / w)
    return out


def write_st_map(path: str | os.PathLike, st: np.ndarray, overwrite: bool = False,
                 attributes: dict[str, Any] | None = None) -> Path:
    """Write an ST map as a float32 RGBA EXR (temporary name, then renamed).

    Parameters
    ----------
    path : str or os.PathLike
        The EXR file to write.
    st : numpy.ndarray
        ``H x W x 4`` (s, t, 0, A), as :func:`st_map` makes it.
    overwrite : bool
        False refuses to replace an existing file.
    attributes : dict, optional
        Header attributes to store beside the channels (the cameras' specs, say).

    Returns
    -------
    pathlib.Path
        The path written.

    Raises
    ------
    FileExistsError
        The file exists and ``overwrite`` is False.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from lenslab import Camera
    >>> from lenslab.stmap import read_st_map, st_map, write_st_map
    >>> cam = Camera.from_spec("fisheye:fov=180", (16, 16))
    >>> path = write_st_map(pathlib.Path(tempfile.mkdtemp()) / "map.exr", st_map(cam, cam))
    >>> read_st_map(path)[8, 8].tolist()  # pixel (8, 8): s = 8.5 / 16, t = 1 - 8.5 / 16
    [0.53125, 0.46875, 0.0, 1.0]
    """
    from lenslab.io import write

    return write(path, st, format="exr", overwrite=overwrite, pixel_type="float",
                 channels=["R", "G", "B", "A"], attributes=attributes or {})


def read_st_map(path: str | os.PathLike, source: bool = False) -> np.ndarray | tuple[np.ndarray, tuple | None]:
    """Read an ST map made by any tool (with ``source``: and the source its mark records, see
    :func:`lenslab.stmap_frame.recorded_source`).

    Parameters
    ----------
    path : str or os.PathLike
        A float image (EXR, or any float format lenslab reads) with s and t in its first two channels
        and, if present, validity in the fourth (``A > 1/2``). Without alpha, every pixel whose ``s, t``
        is finite and inside [0, 1] counts. A map of integer codes (8- or 16-bit PNG, TIFF, PPM) holds
        coordinates, not colours: its codes over their maximum, never sRGB-decoded.
    source : bool
        Also return the source lens spec and size ``(SPEC, (W, H))`` the map's ``lenslab:stmap`` mark records.

    Returns
    -------
    numpy.ndarray
        float32 ``H x W x 4`` (s, t, 0, A), ``A`` in {0, 1} and ``s = t = 0`` where it is 0; with
        ``source``, a pair of it and the recorded ``(SPEC, (W, H))`` of the source (or None).

    Raises
    ------
    lenslab.errors.WarpError
        An image with one channel, or one where no pixel points into the source.
    lenslab.errors.FormatError
        A file lenslab cannot read.

    Examples
    --------
    See :func:`write_st_map`.
    """
    from lenslab.io import read

    img, meta = read(path, rec709=False, raw=True)
    if img.shape[2] < 2:
        raise WarpError(f"{path}: an ST map needs s and t in its first two channels; this image has one")
    s, t = img[..., 0], img[..., 1]
    finite = np.isfinite(s) & np.isfinite(t)
    if img.shape[2] >= 4:
        ok = finite & (img[..., 3] > 0.5)
    else:
        ok = finite & (s >= 0) & (s <= 1) & (t >= 0) & (t <= 1)
    if not ok.any():  # every output pixel would be transparent: not a map of this kind
        which = "its alpha is 0 (or s, t not finite) everywhere" if img.shape[2] >= 4 else \
            "no pixel has finite s and t within [0, 1]"
        raise WarpError(f"{path}: no pixel of this image points into the source ({which}); is it an ST map?")
    # in the image's own memory when it is one (a map of a large output: no second image of its size)
    own = img.dtype == np.float32 and img.shape[2] == 4 and img.flags.c_contiguous and img.flags.writeable
    st = img if own else np.zeros(img.shape[:2] + (4,), dtype=np.float32)
    for c, v in ((0, s), (1, t)):
        st[..., c] = v
        np.copyto(st[..., c], np.float32(0.0), where=~ok)
    st[..., 2] = 0.0
    st[..., 3] = ok
    if source:
        from lenslab.stmap_frame import recorded_source

        return st, recorded_source(meta)
    return st


def source_positions(st: np.ndarray, src_size: tuple[int, int]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Source pixel positions (lenslab's continuous coordinates, float64) and validity of a map's entries."""
    sw, sh = src_size
    ok = st[..., 3] > 0.5
    x = st[..., 0].astype(np.float64) * sw
    y = (1.0 - st[..., 1].astype(np.float64)) * sh
    return x, y, ok


def smooth_links(x: np.ndarray, y: np.ndarray, ok: np.ndarray, axis: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The links between neighbouring entries along ``axis`` (1: across, 0: down): their source-pixel
    steps ``(dx, dy)`` and whether each is smooth (both ends valid and not a jump, see JUMP_RATIO).
    Arrays have one entry fewer along ``axis``."""
    dx, dy = np.diff(x, axis=axis), np.diff(y, axis=axis)
    both = np.diff(ok.astype(np.int8), axis=axis) == 0
    both &= np.delete(ok, 0, axis=axis)
    length = np.where(both, np.hypot(dx, dy), np.inf)
    n = length.shape[axis]
    edge = np.full_like(np.take(length, [0], axis=axis), np.inf)
    before = np.concatenate([edge, np.take(length, range(n - 1), axis=axis)], axis=axis)
    after = np.concatenate([np.take(length, range(1, n), axis=axis), edge], axis=axis)
    near = np.minimum(before, after)
    with np.errstate(invalid="ignore"):
        smooth = both & ~(length > JUMP_RATIO * near + JUMP_SLACK)
    return dx, dy, smooth


class MapGrid:
    """An ST map's source positions and the smoothness of the links between its entries, worked out
    once for a whole warp (see :func:`map_samples`)."""

    def __init__(self, st: np.ndarray, src_size: tuple[int, int]):
        self.x, self.y, self.ok = source_positions(st, src_size)
        self.sx = smooth_links(self.x, self.y, self.ok, 1)[2]  # (h, w - 1)
        self.sy = smooth_links(self.x, self.y, self.ok, 0)[2]  # (h - 1, w)


def map_samples(st: np.ndarray | MapGrid, src_size: tuple[int, int], offsets: np.ndarray, r0: int = 0,
                r1: int | None = None):
    """Index coordinates (float32 ``h x W x S``, the centre of source pixel k at k) and validity of the
    sub-pixel samples at ``offsets`` (``S x 2`` in [0, 1]) of the output pixels of rows ``r0:r1``.

    The map holds pixel centres; a sample elsewhere interpolates it bilinearly from the four nearest
    centres (clamped at the image's edges), unless a link between them is not smooth (a jump, or an
    entry without a ray; see :func:`smooth_links`): it then takes its own pixel's entry.
    """
    grid = st if isinstance(st, MapGrid) else MapGrid(st, src_size)
    x, y, ok, sx, sy = grid.x, grid.y, grid.ok, grid.sx, grid.sy
    h, w = ok.shape
    r1 = h if r1 is None else r1
    xs = np.empty((r1 - r0, w, len(offsets)), dtype=np.float32)
    ys = np.empty_like(xs)
    valid = np.empty(xs.shape, dtype=bool)
    jj, ii = np.mgrid[r0:r1, 0:w]
    for k, (ox, oy) in enumerate(np.asarray(offsets, dtype=np.float64)):
        gx, gy = ii + ox - 0.5, jj + oy - 0.5  # position on the grid of centres
        x0 = np.clip(np.floor(gx).astype(np.intp), 0, w - 1)
        y0 = np.clip(np.floor(gy).astype(np.intp), 0, h - 1)
        x1, y1 = np.minimum(x0 + 1, w - 1), np.minimum(y0 + 1, h - 1)
        fx = np.clip(gx - x0, 0.0, 1.0)
        fy = np.clip(gy - y0, 0.0, 1.0)
        corners = [(y0, x0), (y0, x1), (y1, x0), (y1, x1)]
        cx = np.stack([x[c] for c in corners])
        cy = np.stack([y[c] for c in corners])
        smooth = np.stack([ok[c] for c in corners]).all(axis=0)
        if w > 1:  # the links across the top and bottom pairs and down the left and right pairs
            lx = np.minimum(x0, w - 2)
            smooth &= np.where(x1 > x0, sx[y0, lx] & sx[y1, lx], True)
        if h > 1:
            ly = np.minimum(y0, h - 2)
            smooth &= np.where(y1 > y0, sy[ly, x0] & sy[ly, x1], True)
        wts = np.stack([(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy])
        xs[..., k] = np.where(smooth, (wts * cx).sum(axis=0), x[r0:r1]) - 0.5
        ys[..., k] = np.where(smooth, (wts * cy).sum(axis=0), y[r0:r1]) - 0.5
        valid[..., k] = ok[r0:r1]
    np.copyto(xs, 0.0, where=~valid)
    np.copyto(ys, 0.0, where=~valid)
    return xs, ys, valid


#: output pixels per band of a one-sample warp, whose source positions are made band by band: a few MB a thread
BAND_POINTS = 1 << 16


def warp_with_st_map(image: np.ndarray, st: np.ndarray, filter: str = "bilinear", samples: int = 1,
                     antialias: bool = False,
                     progress: Callable[[int], None] | None = None,
                     alpha_channel: bool | None = None, looked: Looked | None = None,
                     into: tuple | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Warp ``image`` by an ST map (made by lenslab or any other tool); ``alpha_channel=False``: data
    channels only, none settled as alpha.

    One sample per pixel goes through the engine's :func:`~lenslab.warp.given.warp_with_map`
    (lenslab's filters, and its footprint prefilter with ``antialias``); ``samples`` > 1 takes that
    many stratified samples per pixel, the map interpolated between pixel centres
    (:func:`map_samples`). Taps outside the source clamp to its edge.

    Parameters
    ----------
    image : numpy.ndarray
        The source, ``H x W x C`` or ``H x W``, linear values.
    st : numpy.ndarray
        The map, ``h x w x 4`` (s, t, 0, A), as :func:`st_map` or :func:`read_st_map` give it, or ``h x w x 2``
        as a warp holds it (:func:`lenslab.stmap_rows.packed`).
    filter : str
        A filter of :data:`lenslab.warp.FILTERS` (``nearest``, ``bilinear``, ``bicubic``, ``lanczos``).
    samples : int
        Samples per output pixel (stratified), 1 or more.
    antialias : bool
        The footprint prefilter (with ``samples=1`` only).
    progress : callable, optional
        Called with the number of output rows done.
    alpha_channel : bool, optional
        Whether the image's last channel is alpha: None decides by the channel count (2 or 4), False
        keeps every channel as data (none clipped to [0, 1] or used as coverage), True makes the last one
        alpha (an image of two channels or more).
    looked : lenslab.warp.minification.Looked, optional
        With ``antialias``: what the map's footprints show (whether it shrinks the source anywhere, as
        :func:`lenslab.warp.minification.shrinks` says).
    into : tuple of numpy.ndarray, optional
        ``(image, alpha)`` float32 arrays of the output's shapes to draw into (the channels of one RGBA image,
        :func:`lenslab.io.alpha.room_for_alpha`); ``(image or None, None)``: no coverage kept, returned as None.

    Returns
    -------
    image : numpy.ndarray
        float32 ``h x w x C`` (or ``h x w``), colour premultiplied by the coverage.
    alpha : numpy.ndarray
        float32 ``h x w`` coverage, 0 where the map has no ray.

    Raises
    ------
    lenslab.errors.WarpError
        An unknown filter, or ``antialias`` with ``samples`` > 1.

    Examples
    --------
    The identity map gives the image back, to the last bit:

    >>> import numpy as np
    >>> from lenslab import Camera
    >>> from lenslab.stmap import st_map, warp_with_st_map
    >>> cam = Camera.from_spec("equirect", (8, 4))
    >>> image = np.arange(32, dtype=np.float32).reshape(4, 8)
    >>> out, alpha = warp_with_st_map(image, st_map(cam, cam))
    >>> bool(np.array_equal(out, image)), float(alpha.min())
    (True, 1.0)
    """
    from lenslab.errors import check_image_shape
    from lenslab.filters import filter_named
    from lenslab.stmap_rows import band_positions, unpacked
    from lenslab.warp.filters import sample
    from lenslab.warp.checks import finite_given
    from lenslab.warp.given import draw_rows, warp_with_map
    from lenslab.warp.maps import sample_pattern
    from lenslab.warp.seam import Border

    filter = filter_named(filter)
    if antialias and samples != 1:
        raise WarpError("with an ST map, give either --antialias or --samples, not both")
    size = (image.shape[1], image.shape[0])
    if antialias:
        x, y, ok = source_positions(unpacked(st), size)
        return warp_with_map(image, np.stack([x, y], axis=-1), ok, filter=filter, antialias=antialias,
                             progress=progress, alpha_channel=alpha_channel, looked=looked, into=into)
    img = check_image_shape(image, channels=None)
    src = finite_given(np.ascontiguousarray(img[..., None] if img.ndim == 2 else img, dtype=np.float32))
    offsets = sample_pattern(int(samples))
    grid = None if samples == 1 else MapGrid(unpacked(st), size)

    def draw(r0, r1, o, a):  # each band's source positions made as it is drawn (lenslab.stmap_rows)
        xs, ys, ok = map_samples(grid, size, offsets, r0, r1) if grid else \
            (p[..., None] for p in band_positions(st, size, r0, r1))
        sample(src, xs, ys, ok, Border(), filter, o, a)

    out, alpha = draw_rows(src, st.shape[:2], draw, progress, alpha_channel, into, per_pixel=len(offsets),
                           points=(1 << 18) if grid else BAND_POINTS)
    return (out[..., 0] if img.ndim == 2 else out), alpha
