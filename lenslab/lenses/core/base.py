"""The lens interface: continuous pixel coordinates <-> unit ray directions in camera space.

Conventions (see ``docs/conventions.md``):

- pixel (x, y): x right, y down, origin at the top-left *corner* of the image; centres at (x+0.5, y+0.5);
- normalised coordinates ``u = 2x/W - 1`` and ``v = (1 - 2y/H) * H/W`` (same scale on both axes);
- camera space: +x right, +y up, +z forward (the optical axis).

Every model is one small subclass of :class:`Lens` that states its equation in its docstring and
implements both directions, each returning a validity mask. Arrays go in with any leading shape
(``(..., 2)`` pixels, ``(..., 3)`` directions) and come out with the same leading shape, float64.
No NaN or inf ever leaves a model: where ``valid`` is False the returned values are 0.
"""

from __future__ import annotations

from typing import Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from lenslab.errors import LensError
from lenslab.params import Param  # noqa: F401  (the one parameter type; lens modules import it from here)
from lenslab.lenses.core.arrays import FLOAT, as_points, clean, normalize  # noqa: F401  (lens modules import them from here)
from lenslab.lenses.core.protocol import (  # noqa: F401  (the records the hooks return)
    Across, DirKernel, Field, Piece, PixelKernel, ReferencePoint, Seams)

def _one_point(method, last: int):
    """``method`` taking ``(..., last)`` points, also for a single point of shape ``(last,)``: a model's
    own pixel-level map need only handle arrays of points."""
    import functools

    @functools.wraps(method)
    def maps(self, points, *args, **kwargs):
        arr = np.asarray(points)
        if arr.ndim == 1 and arr.shape[0] == last:
            out, ok = method(self, arr[None], *args, **kwargs)
            return out[0], ok[0]
        return method(self, points, *args, **kwargs)

    return maps


class Lens:
    """A lens model bound to an image size ``width x height``.

    Subclasses set ``name`` and ``params`` and implement the two normalised-coordinate maps
    :meth:`uv_to_dir` and :meth:`dir_to_uv` (or override the pixel-level methods directly).
    """

    def __init_subclass__(cls, **kw):
        super().__init_subclass__(**kw)
        for method, last in (("pixel_to_dir", 2), ("dir_to_pixel", 3)):
            if method in cls.__dict__:
                setattr(cls, method, _one_point(cls.__dict__[method], last))

    name: ClassVar[str] = ""
    summary: ClassVar[str] = ""
    params: ClassVar[tuple[Param, ...]] = ()
    #: other names the spec parser accepts (a former name, a common one)
    aliases: ClassVar[tuple[str, ...]] = ()
    #: where the model's formula comes from (a paper, a library), shown in the docs
    references: ClassVar[tuple[str, ...]] = ()
    #: ``(spec, (width, height))`` pairs every conformance test runs the model with (each model its own:
    #: a subclass does not inherit them); at least one per model
    examples: ClassVar[tuple[tuple[str, tuple[int, int]], ...]] = ()
    #: values pinned from outside lenslab (the paper's formula in float64, OpenCV, lensfun, pycolmap,
    #: ffmpeg): :class:`ReferencePoint` records the conformance suite checks both ways (each model its own)
    reference_points: ClassVar[tuple["ReferencePoint", ...]] = ()
    #: ``(true spec, perturbed start spec, fitted parameters)`` that ``lenslab fit`` recovers exactly on a
    #: 256 x 192 image (each model with float parameters its own; the fit tests run them all)
    fit_examples: ClassVar[tuple[tuple[str, str, str], ...]] = ()

    def __init__(self, width: int, height: int, **values: Any):
        self.width, self.height = check_size(width, height)
        known = {p.name: p for p in self.params}
        unknown = sorted(set(values) - set(known))
        if unknown:
            raise LensError(
                f"{self.name}: unknown parameter(s) {', '.join(unknown)}; valid: "
                + (", ".join(known) or "none")
            )
        for p in self.params:
            setattr(self, p.name, p.convert(self.name, values.get(p.name, p.default)))
        self._check()

    # -- hooks -----------------------------------------------------------------------------
    def _check(self) -> None:
        """Cross-parameter validation (raise LensError)."""

    def uv_to_dir(self, uv: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        raise NotImplementedError

    def dir_to_uv(self, d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        raise NotImplementedError

    # -- what the warp engine asks (lenslab.lenses.core.protocol); defaults hold for any model ----
    def seams(self) -> Seams:
        """How the image continues beyond its edges: a period in x (a full-turn panorama) and poles
        whose rows continue on the opposite meridian. Default: none, taps clamp to the edge pixel."""
        return Seams()

    def pieces(self) -> tuple[Piece, ...]:
        """The rectangles of a piecewise image (cube faces, tiles, dual-fisheye halves), each with
        what lies across its edges for cube-like layouts. Default: one piece, the whole image."""
        return (Piece(0.0, 0.0, float(self.width), float(self.height)),)

    def pixel_kernel(self) -> PixelKernel | None:
        """A compiled ``dir -> pixel`` (see :class:`~lenslab.lenses.core.protocol.PixelKernel`), or None
        (the default): the engine then calls the vectorised :meth:`dir_to_pixel`. A model whose kernel does
        what :meth:`dir_to_pixel` does (normalise, :meth:`dir_to_uv`, :meth:`uv_to_pixel`, :meth:`snap_to_image`)
        has it run there too (:func:`lenslab.lenses.core.native.kernel_holds`)."""
        return None

    def dir_kernel(self) -> DirKernel | None:
        """A compiled ``pixel -> dir`` (:class:`~lenslab.lenses.core.protocol.DirKernel`) that :meth:`pixel_to_dir`
        runs, or None (the default: the NumPy steps, :meth:`pixel_to_uv` then :meth:`uv_to_dir`)."""
        return None

    def field(self) -> Field | None:
        """Cones holding every direction the lens sees (:class:`~lenslab.lenses.core.protocol.Field`), or None
        (the default: no bound, it may see any direction)."""
        return None

    def source_view_count(self) -> int:
        """How many readings :meth:`source_views` gives per direction (default 1: one pixel per ray)."""
        return 1

    def source_views(self, dirs) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """As a source, where to read each direction: ``[(xy, valid, weight), ...]``, one entry per view
        (:meth:`source_view_count` of them; float64 positions ``(..., 2)``, bool, float64 weights that
        sum to 1 where any view is valid and are 0 where that view is not). A lens that sees a
        direction twice (overlapping lenses) blends them. Default: :meth:`dir_to_pixel`, weight 1."""
        xy, ok = self.dir_to_pixel(dirs)
        return [(xy, ok, ok.astype(np.float64))]

    def column_scale(self, y) -> np.ndarray | float:
        """Length on the sphere of one pixel step in x relative to one step in y, at rows ``y``: how
        much a map error in x counts (a full-sphere equirect's columns crowd toward the poles,
        cos(latitude)). Default 1."""
        return 1.0

    def channel_lenses(self) -> tuple["Lens", "Lens", "Lens"] | None:
        """One lens per R, G, B channel (chromatic aberration), or None (the default: one lens for all).

        As a destination, output channel ``c`` at a pixel takes its ray from channel lens ``c``; as a
        source, channel ``c`` is read at channel lens ``c``'s :meth:`dir_to_pixel`. Alpha stays one
        per pixel, from the G lens. Extra channels beyond three follow G."""
        return None

    def size_note(self) -> str | None:
        """One line on what this image size does to the model (a cube map whose faces are not square whole
        pixels), for the commands to print as a note; None (the default) when any size suits it."""
        return None

    def pixels_per_degree(self) -> float:
        """Angular resolution of the image as a source: pixels per degree down its columns, from which a view made
        of it without a given size takes its size (180 degrees at this resolution fill a default view's rows).
        Default: the rows of the first piece over the angle its middle column spans where it has rays (the mean
        where the resolution varies: :mod:`lenslab.lenses.core.resolution`); an equirect's rows over its latitudes."""
        from lenslab.lenses.core.resolution import column_pixels_per_degree

        return column_pixels_per_degree(self)

    def falloff(self, xy) -> np.ndarray | None:
        """Relative illumination (vignetting, 1 on the axis) at continuous pixel positions ``(..., 2)``,
        float64 ``(...)``, or None (the default: 1 everywhere). As a destination the output is
        multiplied by it; as a source the sample is divided by it (never by less than
        ``lenslab.lenses.core.protocol.MIN_FALLOFF``)."""
        return None

    # -- pixel level -----------------------------------------------------------------------
    @property
    def aspect(self) -> float:
        """H / W: the range of v is [-aspect, aspect]."""
        return self.height / self.width

    def pixel_to_uv(self, xy: np.ndarray) -> np.ndarray:
        xy = np.asarray(xy, dtype=FLOAT)
        uv = np.empty(xy.shape, dtype=FLOAT)
        u, v = uv[..., 0], uv[..., 1]
        np.multiply(xy[..., 0], 2.0, out=u)  # u = 2x/W - 1, in this order: exact 0 at the centre
        u /= self.width
        u -= 1.0
        np.multiply(xy[..., 1], 2.0, out=v)  # v = (1 - 2y/H) * H/W
        v /= self.height
        np.subtract(1.0, v, out=v)
        if self.width != self.height:
            v *= self.aspect
        return uv

    def uv_to_pixel(self, uv: np.ndarray) -> np.ndarray:
        uv = np.asarray(uv, dtype=FLOAT)
        xy = np.empty(uv.shape, dtype=FLOAT)
        x, y = xy[..., 0], xy[..., 1]
        np.add(uv[..., 0], 1.0, out=x)  # x = (u + 1) W/2
        x *= 0.5 * self.width
        if self.width != self.height:  # y = (1 - v / aspect) H/2
            np.divide(uv[..., 1], self.aspect, out=y)
            np.subtract(1.0, y, out=y)
        else:
            np.subtract(1.0, uv[..., 1], out=y)
        y *= 0.5 * self.height
        return xy

    #: pixels up to this far outside the image (in px) still count as inside and are moved onto the
    #: edge: a direction computed from an edge pixel comes back a few ulps (or, for the numerically
    #: inverted models, up to ~1e-9 px) off the edge, and must still be seen
    edge_slack: ClassVar[float] = 1e-6

    def snap_to_image(self, xy: np.ndarray) -> np.ndarray:
        """Validity of pixel positions (inside the image, within :attr:`edge_slack`); those within
        the slack outside the image are moved onto its edge, in place."""
        e = self.edge_slack
        x, y = xy[..., 0], xy[..., 1]
        ok = x >= -e
        ok &= x <= self.width + e
        ok &= y >= -e
        ok &= y <= self.height + e
        np.clip(x, 0.0, self.width, out=x)
        np.clip(y, 0.0, self.height, out=y)
        return ok

    def in_image(self, xy: np.ndarray) -> np.ndarray:
        x, y = xy[..., 0], xy[..., 1]
        ok = x >= 0
        ok &= x <= self.width
        ok &= y >= 0
        ok &= y <= self.height
        return ok

    def pixel_to_dir(self, xy: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """Unit ray directions for continuous pixel coordinates.

        Parameters
        ----------
        xy : array_like
            ``(..., 2)`` pixel coordinates: x right, y down, origin at the image's top-left corner,
            pixel centres at ``+0.5``.

        Returns
        -------
        dirs : numpy.ndarray
            float64 ``(..., 3)`` unit directions in camera space (``+x`` right, ``+y`` up, ``+z``
            forward); 0 where invalid, never NaN or inf.
        valid : numpy.ndarray
            bool ``(...)``: whether the lens has a ray there (e.g. inside a fisheye's circle).
        """
        from lenslab.lenses.core.native import pixel_to_dir_through

        return pixel_to_dir_through(self, xy, self._uv_pixel_to_dir)

    def _uv_pixel_to_dir(self, xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Pixels (float64 ``(..., 2)``) -> directions through :meth:`pixel_to_uv` and :meth:`uv_to_dir`."""
        with np.errstate(all="ignore"):
            d, valid = self.uv_to_dir(self.pixel_to_uv(xy))
        with np.errstate(over="ignore", invalid="ignore"):
            valid = np.logical_and(valid, np.isfinite(np.einsum("...i,...i->...", xy, xy)))
        return clean(d, valid, inplace=True)

    def dir_to_pixel(self, dirs: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """Continuous pixel coordinates where the lens sees directions.

        Parameters
        ----------
        dirs : array_like
            ``(..., 3)`` directions in camera space; they need not be unit length.

        Returns
        -------
        xy : numpy.ndarray
            float64 ``(..., 2)`` pixel coordinates; 0 where invalid, never NaN or inf.
        valid : numpy.ndarray
            bool ``(...)``: False where the model cannot see the direction or where it falls outside
            the image.
        """
        from lenslab.lenses.core.native import dir_to_pixel_through

        return dir_to_pixel_through(self, dirs, self._any_dir_to_pixel)

    def _any_dir_to_pixel(self, d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Directions of any length (float64 ``(..., 3)``) -> pixels: normalised, then :meth:`_uv_dir_to_pixel`;
        zero and non-finite directions are invalid."""
        n2 = np.einsum("...i,...i->...", d, d)
        nonzero = (n2 > 0) & np.isfinite(n2)
        d = d / np.sqrt(n2)[..., None]
        if not nonzero.all():
            d[~nonzero] = (0.0, 0.0, 1.0)  # any unit vector; flagged invalid below
        xy, valid = self._uv_dir_to_pixel(d)
        if not nonzero.all():
            valid &= nonzero
            np.copyto(xy, 0.0, where=~valid[..., None])
        return xy, valid

    def dir_to_pixel_unit(self, d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`dir_to_pixel` for directions already known to be finite unit vectors (float64
        ``(..., 3)``): skips the normalisation, for callers that hold such directions (tiles)."""
        if type(self).dir_to_pixel is not Lens.dir_to_pixel or self.pixel_kernel() is not None:
            return self.dir_to_pixel(d)  # a model with its own pixel-level inverse, or a compiled one
        return self._uv_dir_to_pixel(d)

    def _uv_dir_to_pixel(self, d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Unit directions -> pixels through :meth:`dir_to_uv`, with the image test."""
        with np.errstate(all="ignore"):
            uv, valid = self.dir_to_uv(d)
            xy = self.uv_to_pixel(uv)
        valid = np.logical_and(valid, self.snap_to_image(xy))  # also False for NaN coordinates
        np.copyto(xy, 0.0, where=~valid[..., None])
        return xy, valid

    def pixel_origin(self, xy) -> np.ndarray:
        """Ray origins relative to the camera's eye, in camera space (zero for a single-eye lens)."""
        xy = np.asarray(xy, dtype=FLOAT)
        return np.zeros(xy.shape[:-1] + (3,), dtype=FLOAT)

    @property
    def eye_offsets(self) -> np.ndarray:
        """Distinct eye offsets (camera space) used by this lens, shape (n, 3); one zero row by default."""
        return np.zeros((1, 3), dtype=FLOAT)

    # -- identity --------------------------------------------------------------------------
    def param_values(self) -> dict[str, Any]:
        return {p.name: getattr(self, p.name) for p in self.params}

    #: whether the lens describes a sensor's pixels as the camera stored them (a calibration's intrinsics): a photo
    #: shown turned by its EXIF orientation is warped from its stored frame (a lensfun profile, radial about the
    #: centre and scaled by the shorter side, applies to the photo as shown)
    sensor_frame: bool = False

    #: parameters left out of :meth:`spec` at these values, which mean "derived from the others" (``vfov=0``:
    #: square pixels), so a printed spec is one a user would type
    quiet_defaults: dict[str, Any] = {}

    def spec(self) -> str:
        """Canonical spec string, e.g. ``fisheye:fov=180,mapping=equisolid`` (size not included; parameters at
        their :attr:`quiet_defaults` left out). It parses back to the same lens."""
        parts = []
        for p in self.params:
            val = getattr(self, p.name)
            if p.name in self.quiet_defaults and val == self.quiet_defaults[p.name]:
                continue
            parts.append(f"{p.name}={format_number(val)}" if isinstance(val, float) else f"{p.name}={val}")
        return self.name + (":" + ",".join(parts) if parts else "")

    def to_dict(self) -> dict[str, Any]:
        return {"model": self.name, "size": [self.width, self.height], **self.param_values()}

    def with_size(self, width: int, height: int) -> "Lens":
        return type(self)(width, height, **self.param_values())

    def __repr__(self) -> str:
        return f"<{self.spec()} {self.width}x{self.height}>"

    def __eq__(self, other: object) -> bool:
        return (
            isinstance(other, Lens)
            and type(other) is type(self)
            and (self.width, self.height) == (other.width, other.height)
            and self.to_dict() == other.to_dict()
        )

    def __hash__(self) -> int:
        return hash((self.spec(), self.width, self.height))


Lens.pixel_to_dir = _one_point(Lens.pixel_to_dir, 2)  # the generic maps too (through uv_to_dir)
Lens.dir_to_pixel = _one_point(Lens.dir_to_pixel, 3)


def format_number(val: float) -> str:
    """Shortest text that reads back as the same float: ``0.3``, ``90``, ``1e-05``."""
    text = repr(float(val))
    return text[:-2] if text.endswith(".0") else text


MAX_SIDE = 1 << 17  # 131072 px: larger sides are refused as absurd


def check_size(width, height) -> tuple[int, int]:
    try:
        w, h = int(width), int(height)
    except (TypeError, ValueError):
        raise LensError(f"image size must be two integers, got {width!r} x {height!r}") from None
    if w != width or h != height or not (1 <= w <= MAX_SIDE and 1 <= h <= MAX_SIDE):
        raise LensError(f"image size {width} x {height} is invalid: each side must be an integer in 1..{MAX_SIDE}")
    from lenslab.inputs.limits import MAX_PIXELS

    if w * h > MAX_PIXELS:  # every size (--size, a camera file's resolution, a tile) meets the same cap
        raise LensError(f"image size {w} x {h} is {w * h} pixels, beyond the limit of {MAX_PIXELS} "
                        "(LENSLAB_MAX_PIXELS raises it)")
    return w, h
