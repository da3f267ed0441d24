"""Cube maps: six 90-degree perspective faces in the 3x2 and 6x1 layouts of ffmpeg's v360 filter."""

from __future__ import annotations

import numpy as np

from lenslab.errors import LensError
from lenslab.lenses.base import FLOAT, Lens, Param, as_points, clean, normalize
from lenslab.lenses.registry import register

#: per face, camera-space axes (A, B, C) with  d ~ uf A + vf B + C, where (uf, vf) run over [-1, 1]
#: left to right and top to bottom of the face (ffmpeg v360's face orientations, expressed in the
#: lenslab frame x right, y up, z forward)
FACE_AXES = {
    "r": ((0, 0, -1), (0, -1, 0), (1, 0, 0)),    # right:   d = (1, -vf, -uf)
    "l": ((0, 0, 1), (0, -1, 0), (-1, 0, 0)),    # left:    d = (-1, -vf, uf)
    "u": ((1, 0, 0), (0, 0, 1), (0, 1, 0)),      # up:      d = (uf, 1, vf)    (bottom edge meets front)
    "d": ((1, 0, 0), (0, 0, -1), (0, -1, 0)),    # down:    d = (uf, -1, -vf)  (top edge meets front)
    "f": ((1, 0, 0), (0, -1, 0), (0, 0, 1)),     # front:   d = (uf, -vf, 1)
    "b": ((-1, 0, 0), (0, -1, 0), (0, 0, -1)),   # back:    d = (-uf, -vf, -1)
}
LAYOUTS = {"3x2": (3, 2), "6x1": (6, 1)}
#: pixels by which dir_to_pixel keeps a point off the right and bottom edges of its face
BORDER_NUDGE = 1e-9


@register
class Cubemap(Lens):
    r"""Cube map: six 90-degree perspective faces, laid out 3x2 or 6x1 as ffmpeg's v360 filter does.

    Faces are ``W/cols x H/rows``, numbered row by row (``face = row * cols + col``); ``order`` names
    the direction of each face in that numbering, ffmpeg's default ``rludfb``: right, left, up,
    down, front, back (3x2: top row right-left-up, bottom row down-front-back). Inside a face,
    ``uf = 2 (x - col W/cols) / (W/cols) - 1`` and ``vf = 2 (y - row H/rows) / (H/rows) - 1``, and::

        right d ~ (1, -vf, -uf)    left d ~ (-1, -vf, uf)    up    d ~ (uf, 1, vf)
        down  d ~ (uf, -1, -vf)    front d ~ (uf, -vf, 1)     back  d ~ (-uf, -vf, -1)

    (the faces of ffmpeg's ``v360=...:c3x2`` / ``c6x1`` output with no rotation, so the four side
    faces are upright and the up and down faces join the front face along their bottom and top edges).
    The inverse picks the face of the largest component of ``d`` (ties: x, then y, then z); a direction
    on a cube edge has two pixel positions, one on each face, and comes back on the first. A pixel
    exactly on a border between faces belongs to the face right of or below it; the inverse keeps its
    points 1e-9 px inside their face's right and bottom edges, so both directions agree.
    """

    name = "cubemap"
    summary = "cube map, six 90-degree faces in ffmpeg v360's 3x2 or 6x1 layout"
    params = (
        Param("layout", "3x2", "face grid: 3x2 (3 columns, 2 rows) or 6x1", choices=tuple(LAYOUTS)),
        Param("order", "rludfb", "direction of each face, row by row: r l u d f b (ffmpeg's in_forder/out_forder)"),
    )

    def _check(self) -> None:
        order = self.order.strip().lower()
        if sorted(order) != sorted("rludfb"):
            raise LensError(
                f"cubemap: order={self.order!r} must name each of the six faces r, l, u, d, f, b exactly once "
                f"(ffmpeg's default is rludfb)"
            )
        self.order = order
        self.cols, self.rows = LAYOUTS[self.layout]
        axes = np.array([FACE_AXES[c] for c in order], dtype=FLOAT)  # (6, 3 vectors, 3)
        self._A, self._B, self._C = axes[:, 0], axes[:, 1], axes[:, 2]
        # slot of each face direction, by the index of its major axis: +x, -x, +y, -y, +z, -z
        self._slot_of_axis = np.array([order.index(c) for c in "rludfb"])

    @property
    def face_size(self) -> tuple[float, float]:
        return self.width / self.cols, self.height / self.rows

    def pixel_to_dir(self, xy):
        with np.errstate(all="ignore"):  # non-finite or absurd pixels are flagged, not warned about
            return self._pixel_to_dir(as_points(xy, 2, "pixel coordinates"))

    def _pixel_to_dir(self, xy):
        ew, eh = self.face_size
        fx = xy[..., 0] / ew
        fy = xy[..., 1] / eh
        col = np.clip(np.floor(fx), 0, self.cols - 1)
        row = np.clip(np.floor(fy), 0, self.rows - 1)
        uf = 2.0 * (fx - col) - 1.0
        vf = 2.0 * (fy - row) - 1.0
        face = (row * self.cols + col).astype(np.intp)
        face = np.where(np.isfinite(fx) & np.isfinite(fy), face, 0)
        d = self._A[face] * uf[..., None]
        d += self._B[face] * vf[..., None]
        d += self._C[face]
        d /= np.sqrt(np.einsum("...i,...i->...", d, d))[..., None]
        return clean(d, self.in_image(xy))

    def dir_to_pixel(self, dirs):
        d = as_points(dirs, 3, "directions")
        a = np.abs(d)
        axis = np.argmax(a, axis=-1)  # 0 x, 1 y, 2 z (first on ties)
        comp = np.take_along_axis(d, axis[..., None], axis=-1)[..., 0]
        slot = self._slot_of_axis[2 * axis + (comp < 0)]
        with np.errstate(all="ignore"):
            t = np.einsum("...i,...i->...", d, self._C[slot])
            uf = np.einsum("...i,...i->...", d, self._A[slot]) / t
            vf = np.einsum("...i,...i->...", d, self._B[slot]) / t
        ew, eh = self.face_size
        col = slot % self.cols
        row = slot // self.cols
        xy = np.empty(d.shape[:-1] + (2,), dtype=FLOAT)
        xy[..., 0] = (col + 0.5 * (uf + 1.0)) * ew
        xy[..., 1] = (row + 0.5 * (vf + 1.0)) * eh
        # a point on a face's right or bottom edge is moved BORDER_NUDGE px back into that face, so
        # that pixel_to_dir (which gives border pixels to the face right of or below them) returns
        # the same direction
        np.minimum(xy[..., 0], (col + 1) * ew - BORDER_NUDGE, out=xy[..., 0])
        np.minimum(xy[..., 1], (row + 1) * eh - BORDER_NUDGE, out=xy[..., 1])
        valid = (t > 0) & self.snap_to_image(xy)
        return clean(xy, valid, inplace=True)
