"""What a lens tells the warp engine beyond its two maps: the records its protocol hooks return.

:class:`~lenslab.lenses.core.base.Lens` answers each hook with a default that holds for any model that only
implements ``uv_to_dir``/``dir_to_uv`` (or the pixel-level methods); a model overrides a hook where it
knows better. The engine asks these hooks and never reads a model's name:

- :meth:`~lenslab.lenses.core.base.Lens.seams` -> :class:`Seams`: how the image continues beyond its edges
  (a full-turn panorama wraps in x; a row beyond a pole continues on the opposite meridian);
- :meth:`~lenslab.lenses.core.base.Lens.pieces` -> tuple of :class:`Piece`: the rectangles of a piecewise
  image (cube faces, tiles, dual-fisheye halves) and, for cube-like layouts, what lies across each edge;
- :meth:`~lenslab.lenses.core.base.Lens.pixel_kernel` -> :class:`PixelKernel` or None: a compiled
  ``dir -> pixel``; :meth:`~lenslab.lenses.core.base.Lens.dir_kernel` -> :class:`DirKernel` or None: a compiled
  ``pixel -> dir``;
- :meth:`~lenslab.lenses.core.base.Lens.field` -> :class:`Field` or None: cones that hold every direction the
  lens sees (the warp marks output regions wholly outside them unseen without evaluating their pixels);
- :meth:`~lenslab.lenses.core.base.Lens.column_scale`: the length on the sphere of one column, per row;
- :meth:`~lenslab.lenses.core.base.Lens.channel_lenses` and :meth:`~lenslab.lenses.core.base.Lens.falloff`:
  chromatic aberration (one lens per R, G, B) and vignetting.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, NamedTuple

import numpy as np

#: edge numbers used by :class:`Across` and :attr:`Piece.across`
LEFT, RIGHT, TOP, BOTTOM = 0, 1, 2, 3
EDGES = ("left", "right", "top", "bottom")


@dataclass(frozen=True)
class Seams:
    """How an image continues beyond its edges (the default: it does not; taps clamp to the edge pixel).

    - ``period_x`` (pixels, 0 = none): column ``x`` and ``x + period_x`` show the same direction
      (a full-turn equirect: ``period_x = W``, column ``-1`` is column ``W - 1``);
    - ``pole_top`` / ``pole_bottom``: the top (bottom) edge is a pole, so the row ``j`` pixels beyond it
      is row ``j - 1`` inside it on the opposite meridian, half a period away (needs ``period_x``).
    """

    period_x: float = 0.0
    pole_top: bool = False
    pole_bottom: bool = False

    @property
    def wraps(self) -> bool:
        return self.period_x > 0.0

    @property
    def has_pole(self) -> bool:
        return self.pole_top or self.pole_bottom


@dataclass(frozen=True)
class Across:
    """What lies across one edge of a :class:`Piece`: edge ``edge`` of piece number ``piece``.

    Positions along an edge run top to bottom on left/right edges and left to right on top/bottom
    edges; ``reversed`` says they run the opposite way on the two sides. A tap ``k + 1/2`` pixels
    beyond the edge (``k = 0, 1, ...``) at position ``s`` reads the pixel ``k + 1/2`` inside the
    neighbour's edge at position ``s`` (or ``length - s`` when reversed).
    """

    piece: int
    edge: int
    reversed: bool = False


@dataclass(frozen=True)
class Piece:
    """One rectangle of a piecewise image, in pixels: ``x0 <= x < x0 + width``, ``y0 <= y < y0 + height``.

    The map of a piecewise image jumps at piece edges, so the engine never interpolates or measures a
    footprint across one. ``across`` (left, right, top, bottom; None for an edge with nothing beyond, or
    for no topology at all) tells a filter tap that leaves the piece which neighbour to read.
    ``lens``/``pose`` describe a piece that is a camera of its own (a tile: its lens in the piece's
    pixel frame and its pose relative to the whole camera); None otherwise. ``eye`` numbers the eye
    of a stereo frame a piece shows (0 left or top, 1 right or bottom; None for no eye): the engine
    warps each output eye from the same eye of a stereo source.
    """

    x0: float
    y0: float
    width: float
    height: float
    across: tuple[Across | None, Across | None, Across | None, Across | None] | None = None
    lens: Any = None
    pose: Any = None
    eye: int | None = None

    @property
    def rect(self) -> tuple[float, float, float, float]:
        return self.x0, self.y0, self.width, self.height


@dataclass(frozen=True)
class PixelKernel:
    """A compiled ``dir -> pixel`` of one lens, ahead-of-time compiled (a function of the C++ extension
    ``lenslab.cxx_kernels``): nothing is compiled when a warp first asks for it.

    ``fn(d, params, xy, ok)`` projects ``d`` (float64, C-contiguous ``(n, 3)``, any length) into ``xy``
    (float64 ``(n, 2)``: the continuous pixel position, pixel centres at +0.5) and ``ok`` (bool ``(n,)``:
    whether the lens sees the direction inside its image), both written in place; zero and non-finite
    directions are not seen, and ``xy = 0`` wherever ``ok`` is False. ``fn`` releases the GIL. ``params``
    is a float64 1-D array of whatever the function needs (image size, parameters), made once per lens.
    :func:`lenslab.lenses.core.native.project_kernel` runs it; :meth:`Lens.dir_to_pixel` runs it for a
    model that has one, and the warp engine for large sources.
    """

    fn: Callable
    params: np.ndarray


@dataclass(frozen=True)
class DirKernel:
    """A compiled ``pixel -> dir`` of one lens (a function of ``lenslab.cxx_kernels``), the other way from
    :class:`PixelKernel`: ``fn(xy, params, d, ok)`` maps continuous pixel positions ``xy`` (float64, C-contiguous
    ``(n, 2)``, pixel centres at +0.5) to unit directions ``d`` (float64 ``(n, 3)``) and ``ok`` (bool ``(n,)``:
    whether the lens has a ray there), both written in place; non-finite pixels have no ray, and ``d = 0``
    wherever ``ok`` is False. It releases the GIL. :func:`lenslab.lenses.core.native.unproject_kernel` runs it;
    :meth:`Lens.pixel_to_dir` runs it for a model that has one (so the warp's exact map does).
    """

    fn: Callable
    params: np.ndarray


@dataclass(frozen=True)
class Field:
    """Where a lens can see: every direction it sees (inside its image, edge slack included) lies within
    ``angles[i]`` radians of the unit vector ``axes[i]``, for every ``i`` (float64 ``(k, 3)`` and ``(k,)``). A cone
    of ``pi/2`` is a half-space: a pinhole's frame is four of them. It is a bound, never a test of a pixel: a
    direction inside every cone may still be unseen."""

    axes: np.ndarray
    angles: np.ndarray


class ReferencePoint(NamedTuple):
    """One pixel and its ray, from a source outside lenslab: ``spec`` at ``size`` (width, height) sees
    ``direction`` (unit, camera space) at continuous pixel ``pixel``; ``source`` says where the numbers
    come from (the paper's equation, ``cv2.projectPoints``, lensfunpy, ...); ``tolerance`` (px) is the
    source's own precision (float64 formulas: 1e-6 px, the project's accuracy)."""

    spec: str
    size: tuple[int, int]
    pixel: tuple[float, float]
    direction: tuple[float, float, float]
    source: str
    tolerance: float = 1e-6


#: a source's falloff is never divided by less than this (a vignetted corner near 0 would blow up noise)
MIN_FALLOFF = 1e-3


#: per edge (left, right, top, bottom): (sign, axis) of its outward vector and of the direction in which
#: positions along it run, in terms of a face's axes A (across, left to right) and B (down)
_EDGE_OUT = ((-1, 0), (1, 0), (-1, 1), (1, 1))
_EDGE_ALONG = ((1, 1), (1, 1), (1, 0), (1, 0))


def cube_pieces(rects, axes) -> tuple[Piece, ...]:
    """Pieces of a cube layout: ``rects[k] = (x0, y0, w, h)`` of face ``k`` and ``axes[k] = (A, B, C)``
    with ``d ~ uf A + vf B + C`` across it (``uf`` left to right, ``vf`` top to bottom, both in [-1, 1]).

    Across each face edge lies the face whose centre axis ``C`` is that edge's outward vector, along its
    edge whose outward vector is this face's ``C`` (the cube folded flat along their common edge)."""
    axes = [np.asarray(a, dtype=np.float64) for a in axes]

    def vec(k, sign_axis):
        sign, which = sign_axis
        return sign * axes[k][which]

    pieces = []
    for f in range(len(axes)):
        across = []
        for e in range(4):
            out = vec(f, _EDGE_OUT[e])
            found = None
            for g in range(len(axes)):
                if g != f and np.allclose(axes[g][2], out):
                    for e2 in range(4):
                        if np.allclose(vec(g, _EDGE_OUT[e2]), axes[f][2]):
                            rev = float(np.dot(vec(f, _EDGE_ALONG[e]), vec(g, _EDGE_ALONG[e2]))) < 0
                            found = Across(g, e2, rev)
            across.append(found)
        pieces.append(Piece(*map(float, rects[f]), across=tuple(across)))
    return tuple(pieces)
