"""Cube maps: six 90-degree perspective faces in the 3x2, 6x1 and 1x6 layouts of ffmpeg's v360 filter,
or a 4x3 cross."""

from __future__ import annotations

import numpy as np

from lenslab.errors import LensError
from lenslab.lenses.core.base import FLOAT, Lens, Param, PixelKernel, ReferencePoint, as_points, clean
from lenslab.lenses.core.protocol import cube_pieces
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
LAYOUTS = {"3x2": (3, 2), "6x1": (6, 1), "1x6": (1, 6), "4x3": (4, 3)}
#: cells of the grid that hold a face, row by row (the others have no rays): the 4x3 cross has the up
#: face above the front, left, front, right and back across the middle and the down face below the front
CELLS = {"3x2": tuple(range(6)), "6x1": tuple(range(6)), "1x6": tuple(range(6)), "4x3": (1, 4, 5, 6, 7, 9)}
#: the face order a layout takes when ``order`` keeps its default, rludfb
DEFAULT_ORDER = {"4x3": "ulfrbd"}
#: pixels by which dir_to_pixel keeps a point off the right and bottom edges of its face
BORDER_NUDGE = 1e-9


@register
class Cubemap(Lens):
    r"""Cube map: six 90-degree perspective faces in a 3x2, 6x1, 1x6 or 4x3-cross layout.

    The first three are ffmpeg v360's ``c3x2``, ``c6x1`` and ``c1x6``.

    Faces are ``W/cols x H/rows``, numbered row by row (``face = row * cols + col``); ``order`` names
    the direction of each face in that numbering, ffmpeg's default ``rludfb``: right, left, up,
    down, front, back (3x2: top row right-left-up, bottom row down-front-back). The 4x3 cross has
    faces in six of its twelve cells (the others have no rays): by default up above the front, then
    left, front, right, back across the middle row and down below the front (``order`` then names the
    faces of those six cells, row by row, ``ulfrbd``). Inside a face,
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
    #: specs and image sizes the conformance tests run on (round trips, extremes)
    examples = (
        ('cubemap:layout=3x2', (8192, 5462)),
        ('cubemap:layout=6x1,order=fbrlud', (8192, 1366)),
        ('cubemap:layout=1x6', (1366, 8192)),
        ('cubemap:layout=4x3', (8192, 6144)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways)
    reference_points = (
        ReferencePoint('cubemap', (600, 400), (330.5, 260.25),
                       (0.27268783271418423, 0.35538824099635485, 0.8940584679153583),
                       'ffmpeg v360 c3x2 (rludfb): the front face is a 90-degree pinhole'),
        ReferencePoint('cubemap', (600, 400), (130.5, 60.25),
                       (0.8940584679153584, 0.35538824099635496, -0.2726878327141843),
                       'ffmpeg v360 c3x2 (rludfb): the right face looks along +x'),
    )
    summary = "cube map, six 90-degree faces in ffmpeg v360's 3x2 or 6x1 layout"
    params = (
        Param("layout", "3x2", "face grid: 3x2 (3 columns, 2 rows), 6x1, 1x6 or the 4x3 cross",
              choices=tuple(LAYOUTS)),
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
        cells = CELLS[self.layout]
        layout_order = DEFAULT_ORDER.get(self.layout, "rludfb") if order == "rludfb" else order
        # per grid cell: the face's axes (zero for empty cells) and whether the cell holds a face
        axes = np.zeros((self.cols * self.rows, 3, 3), dtype=FLOAT)
        axes[list(cells)] = [FACE_AXES[c] for c in layout_order]
        self._used = np.zeros(self.cols * self.rows, dtype=bool)
        self._used[list(cells)] = True
        self._A, self._B, self._C = axes[:, 0], axes[:, 1], axes[:, 2]
        # cell of each face direction, by the index of its major axis: +x, -x, +y, -y, +z, -z
        self._slot_of_axis = np.array([cells[layout_order.index(c)] for c in "rludfb"])
        # every face's A and B are signed unit axes: on the x faces A is along z and B along y, on the
        # y faces A along x and B along z, on the z faces A along x and B along y; keep their signs
        self._sA = axes[:, 0].sum(axis=1)
        self._sB = axes[:, 1].sum(axis=1)

    @property
    def v360_read(self) -> str | None:
        """How ffmpeg's v360 reads this layout as its input (it has no cross)."""
        return None if self.layout == "4x3" else "centre"

    def pieces(self):
        """The six faces, each with the face and edge across each of its edges (the cube folded flat)."""
        ew, eh = self.face_size
        cells = [k for k in range(self.cols * self.rows) if self._used[k]]
        rects = [((k % self.cols) * ew, (k // self.cols) * eh, ew, eh) for k in cells]
        return cube_pieces(rects, [(self._A[k], self._B[k], self._C[k]) for k in cells])

    @property
    def face_size(self) -> tuple[float, float]:
        return self.width / self.cols, self.height / self.rows

    def frame_size(self, height: int) -> tuple[int, int]:
        """The image size of about ``height`` rows whose faces are square and of whole pixels (a default size)."""
        face = max(1, int(height) // self.rows)
        return self.cols * face, self.rows * face

    def default_frame(self, rows: int) -> tuple[int, int]:
        """The size made without ``--size`` from a source of ``rows`` rows: square faces of ``rows // 2`` pixels
        in this layout, whatever it is (768x512 for 3x2, 1536x256 for 6x1 from 512 rows). The other lenses'
        default of ``rows`` rows spans 180 degrees (a 180-degree fisheye), so a face's 90 degrees get half of it:
        every layout samples the view alike."""
        face = max(1, int(rows) // 2)
        return self.cols * face, self.rows * face

    def pixels_per_degree(self) -> float:
        """A face's rows over its 90 degrees, whatever the layout: 256-pixel faces give 512 rows of 180 degrees
        as a 6x1 strip, a 1x6 column and a 3x2 map alike."""
        return self.face_size[1] / 90.0

    def size_note(self) -> str | None:
        """At a size off the layout's aspect (a 3x2 map at 1000x1000) the faces are not square, or not of whole
        pixels: each face's 90 degrees are stretched across it, and no face can be cut out as an image."""
        ew, eh = self.face_size
        if ew == eh and float(ew).is_integer():
            return None
        w, h = self.frame_size(self.height)
        return (f"cubemap:layout={self.layout} at {self.width}x{self.height} has faces of {ew:.6g}x{eh:.6g} pixels, "
                f"not square faces of whole pixels; made at {self.width}x{self.height} as asked, each face's 90 "
                f"degrees stretched to fit (square faces: {self.cols}:{self.rows}, e.g. {w}x{h})")

    def pixel_to_dir(self, xy):
        with np.errstate(all="ignore"):  # non-finite or absurd pixels are flagged, not warned about
            return self._pixel_to_dir(as_points(xy, 2, "pixel coordinates"))

    def _pixel_to_dir(self, xy):
        ew, eh = self.face_size
        fx = xy[..., 0] / ew
        fy = xy[..., 1] / eh
        col = np.clip(np.floor(fx), 0, self.cols - 1)
        row = np.clip(np.floor(fy), 0, self.rows - 1)
        uf = fx - col
        uf *= 2.0
        uf -= 1.0
        vf = fy - row
        vf *= 2.0
        vf -= 1.0
        ok = np.isfinite(fx) & np.isfinite(fy)
        face = row * self.cols
        face += col
        face = np.where(ok, face, 0).astype(np.intp)
        # d = (uf A + vf B + C) / sqrt(uf^2 + vf^2 + 1), one component at a time (A, B, C orthonormal)
        inv = uf * uf
        inv += vf * vf
        inv += 1.0
        np.sqrt(inv, out=inv)
        np.divide(1.0, inv, out=inv)
        d = np.empty(xy.shape[:-1] + (3,), dtype=FLOAT)
        for j in range(3):
            o = d[..., j]
            np.multiply(self._A[:, j].take(face), uf, out=o)
            o += self._B[:, j].take(face) * vf
            o += self._C[:, j].take(face)
            o *= inv
        return clean(d, self.in_image(xy) & ok & self._used.take(face), inplace=True)

    def pixel_kernel(self):
        """The compiled ``dir -> pixel`` (``cubemap_pixels``: the NumPy steps of :meth:`_dir_to_pixel`), or None
        for a subclass that changed one of those steps."""
        from lenslab.lenses.core.native import kernel_holds, lens_kernels

        if not kernel_holds(self, Cubemap, ("_dir_to_pixel", "face_size")):
            return None
        ew, eh = self.face_size
        slot = self._slot_of_axis  # per major axis +x, -x, +y, -y, +z, -z: its face's column, row, signs of A, B
        faces = np.stack([slot % self.cols, slot // self.cols, self._sA.take(slot), self._sB.take(slot)], axis=-1)
        return PixelKernel(lens_kernels().cubemap_pixels, np.concatenate(
            [[self.width, self.height, ew, eh, self.edge_slack, BORDER_NUDGE], faces.ravel()]).astype(FLOAT))

    def dir_to_pixel(self, dirs):
        from lenslab.lenses.core.native import dir_to_pixel_through

        return dir_to_pixel_through(self, dirs, self._dir_to_pixel)

    def _dir_to_pixel(self, d):
        dx, dy, dz = d[..., 0], d[..., 1], d[..., 2]
        a = np.abs(d)
        axis = np.argmax(a, axis=-1)  # 0 x, 1 y, 2 z (the first on ties)
        t = np.take_along_axis(a, axis[..., None], axis=-1)[..., 0]  # |major component| = d . C
        neg = np.take_along_axis(d, axis[..., None], axis=-1)[..., 0] < 0
        slot = self._slot_of_axis.take(2 * axis + neg)
        # uf = d . A / t, vf = d . B / t, with A and B signed axes (see _check)
        uf = np.where(axis == 0, dz, dx)
        uf *= self._sA.take(slot)
        uf /= t
        vf = np.where(axis == 1, dz, dy)
        vf *= self._sB.take(slot)
        vf /= t
        ew, eh = self.face_size
        col = slot % self.cols
        row = slot // self.cols
        xy = np.empty(d.shape[:-1] + (2,), dtype=FLOAT)
        x, y = xy[..., 0], xy[..., 1]
        np.add(uf, 1.0, out=x)
        x *= 0.5
        x += col
        x *= ew
        np.add(vf, 1.0, out=y)
        y *= 0.5
        y += row
        y *= eh
        # a point on a face's right or bottom edge is moved BORDER_NUDGE px back into that face, so
        # that pixel_to_dir (which gives border pixels to the face right of or below them) returns
        # the same direction
        np.minimum(x, (col + 1) * ew - BORDER_NUDGE, out=x)
        np.minimum(y, (row + 1) * eh - BORDER_NUDGE, out=y)
        valid = (t > 0) & np.isfinite(t) & self.snap_to_image(xy)
        return clean(xy, valid, inplace=True)
