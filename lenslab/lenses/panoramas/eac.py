"""Equi-angular cube map (EAC): the cube faces of YouTube's 360 videos, in the 3x2 layout of ffmpeg's v360.

A plain cube map spends more pixels near its face edges than at the centres (``tan`` grows); the
equi-angular cube spaces its pixels evenly in angle instead: across a face, the position ``s`` in
[-1, 1] holds the direction whose cube coordinate is ``tan(pi/4 s)``. Layout (v360's ``eac``)::

    +-------+-------+-------+
    | left  | front | right |     upright
    +-------+-------+-------+
    | down  | back  |  up   |     turned a quarter: the bottom row runs along the back of the cube
    +-------+-------+-------+

v360 also frames the faces with ``pad`` pixels (2 in its ``eac``): at the left and right ends of each
row and above and below each row, not between faces of one row; those pixels have no ray here.
"""

from __future__ import annotations

import numpy as np

from lenslab.lenses.core.base import FLOAT, DirKernel, Lens, Param, PixelKernel, ReferencePoint, as_points, clean
from lenslab.lenses.core.protocol import cube_pieces
from lenslab.lenses.registry import register

#: per slot (row by row), camera-space axes (A, B, C) with  d ~ uf A + vf B + C, where (uf, vf) are the
#: cube coordinates across the face, left to right and top to bottom (v360's eac faces in lenslab's frame)
EAC_AXES = (
    ((0, 0, 1), (0, -1, 0), (-1, 0, 0)),   # left:  d = (-1, -vf, uf)
    ((1, 0, 0), (0, -1, 0), (0, 0, 1)),    # front: d = (uf, -vf, 1)
    ((0, 0, -1), (0, -1, 0), (1, 0, 0)),   # right: d = (1, -vf, -uf)
    ((0, 0, -1), (-1, 0, 0), (0, -1, 0)),  # down:  d = (-vf, -1, -uf)
    ((0, 1, 0), (-1, 0, 0), (0, 0, -1)),   # back:  d = (-vf, uf, -1)
    ((0, 0, 1), (-1, 0, 0), (0, 1, 0)),    # up:    d = (-vf, 1, uf)
)
#: pixels by which dir_to_pixel keeps a point off the right and bottom edges of its face
BORDER_NUDGE = 1e-9


@register
class EquiAngularCubemap(Lens):
    r"""Equi-angular cube map (YouTube's 360 format) in v360's 3x2 layout, pixels evenly spaced in angle.

    Top row left, front, right (upright); bottom row down, back, up, turned a quarter so that the row
    runs along the back of the cube. With ``p`` the pad in pixels (v360's ``eac``: 2, round each row),
    ``c = 3 (x/W - p/W) / (1 - 2p/W)`` (face column ``floor(c)``, ``fx = c - col``) and, in row
    ``r = floor(2y/H)``, ``fy = (y/H - p/H - r/2) / (1/2 - 2p/H)``; then
    ``s = 2 fx - 1``, ``t = 2 fy - 1`` and ``uf = tan(pi/4 s)``, ``vf = tan(pi/4 t)``,
    ``d = normalise(uf A + vf B + C)`` with the face's axes. The inverse takes the face of the largest
    component of ``d`` (ties: x, then y, then z), ``uf = d.A / d.C``, ``vf = d.B / d.C`` and
    ``s = (4/pi) atan(uf)``. A pixel on a border between faces belongs to the face right of or below it.
    """

    name = "eac"
    #: specs and image sizes the conformance tests run on (round trips, extremes)
    examples = (
        ('eac', (8192, 5462)),
        ('eac:pad=2', (8192, 5462)),
    )
    #: pinned from outside lenslab (the conformance suite checks both ways)
    reference_points = (
        ReferencePoint('eac', (600, 400), (330.5, 60.25),
                       (0.2263950980334737, 0.2991740509072396, 0.9269520736533071),
                       'equi-angular cube map (YouTube; ffmpeg v360 eac): position s holds cube coordinate '
                       'tan(pi/4 s)'),
    )
    #: (true spec, perturbed start, fitted parameters) a fit recovers exactly, on a 256 x 192 image
    fit_examples = (
        ('eac:pad=2', 'eac:pad=1', 'pad'),
    )
    summary = "equi-angular cube map (YouTube's 360 format), v360's 3x2 layout"
    #: how ffmpeg's v360 reads this projection as its input (lenslab.warp.compat_v360)
    v360_read = "centre"
    #: the frame the model fills, width / height (the default output size of lenslab warp)
    frame_aspect = 1.5
    params = (
        Param("pad", 0.0, "pixels of padding round each row of faces (v360's eac: 2)", 0.0, 64.0),
    )

    def _check(self) -> None:
        from lenslab.errors import LensError

        axes = np.array(EAC_AXES, dtype=FLOAT)
        self._A, self._B, self._C = axes[:, 0], axes[:, 1], axes[:, 2]
        self._iA, self._sA = np.abs(self._A).argmax(axis=1), self._A.sum(axis=1)
        self._iB, self._sB = np.abs(self._B).argmax(axis=1), self._B.sum(axis=1)
        # slot of each major axis +x, -x, +y, -y, +z, -z (the slot whose C is that axis)
        majors = ((1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1))
        self._slot_of_axis = np.array([EAC_AXES.index(next(a for a in EAC_AXES if a[2] == m)) for m in majors])
        self.pu, self.pv = self.pad / self.width, self.pad / self.height
        if not (self.pu < 0.25 and self.pv < 0.1):
            raise LensError(f"eac: pad={self.pad:g} leaves no room for the faces of a {self.width}x{self.height} image")

    def pieces(self):
        """The six faces, padding left out, each with the face and edge across each of its edges (the
        cube folded flat; equal angles per pixel on both sides of every edge)."""
        fw, fh = self.width * (1.0 - 2.0 * self.pu) / 3.0, self.height * (0.5 - 2.0 * self.pv)
        rects = [(self.pad + (k % 3) * fw, self.pad + (k // 3) * self.height / 2.0, fw, fh) for k in range(6)]
        return cube_pieces(rects, EAC_AXES)

    def default_frame(self, rows: int) -> tuple[int, int]:
        """The size made without ``--size`` from a source of ``rows`` rows over 180 degrees: square faces of
        ``rows // 2`` pixels (90 degrees, as a cube map's), with the padding round each row of faces."""
        face, pad = max(1, int(rows) // 2), float(self.pad)
        return 3 * face + round(2 * pad), 2 * face + round(4 * pad)

    def pixels_per_degree(self) -> float:
        """A face's rows without the padding over its 90 degrees (even in angle across the face): ``H/2 - 2 pad``."""
        return self.height * (0.5 - 2.0 * self.pv) / 90.0

    def dir_kernel(self):
        """The compiled ``pixel -> dir`` (``eac_dirs``: the steps of :meth:`_pixel_to_dir`, its tangents as sine over
        cosine to a few ulps), or None for a subclass that changed one of those steps."""
        from lenslab.lenses.core.native import lens_kernels

        if not all(getattr(type(self), k) is getattr(EquiAngularCubemap, k) for k in ("pixel_to_dir", "_pixel_to_dir",
                                                                                     "in_image")):
            return None
        return DirKernel(lens_kernels().eac_dirs, np.concatenate(
            [[self.width, self.height, self.pu, self.pv, 3.0 / (1.0 - 2.0 * self.pu), 0.5 - 2.0 * self.pv],
             np.array(EAC_AXES, dtype=FLOAT).ravel()]).astype(FLOAT))

    def pixel_to_dir(self, xy):
        from lenslab.lenses.core.native import pixel_to_dir_through

        return pixel_to_dir_through(self, xy, self._pixel_to_dir)

    def v360_pixel_to_dir(self, xy):
        """The rays v360 gives this output's pixels: the padding continues its face's plane, linearly (the
        cube coordinate is ``s`` itself past ``|s| = 1``, where it meets ``tan(pi/4 s)``)."""
        with np.errstate(all="ignore"):
            return self._pixel_to_dir(as_points(xy, 2, "pixel coordinates"), padding=True)

    def _pixel_to_dir(self, xy, padding=False):
        t = xy[..., 0] / self.width
        t -= self.pu
        t *= 3.0 / (1.0 - 2.0 * self.pu)
        ok = (t >= 0.0) & (t <= 3.0) | padding
        col = np.clip(np.floor(t), 0, 2)
        fx = t - col
        yn = xy[..., 1] / self.height
        row = np.clip(np.floor(2.0 * yn), 0, 1)
        fy = (yn - self.pv - 0.5 * row) / (0.5 - 2.0 * self.pv)
        ok &= ((fy >= 0.0) & (fy <= 1.0) | padding) & self.in_image(xy)
        ok &= np.isfinite(t) & np.isfinite(yn)
        slot = np.where(ok, row * 3 + col, 0).astype(np.intp)
        uf, vf = 2.0 * fx - 1.0, 2.0 * fy - 1.0
        if padding:  # v360's padding: linear past the face's edge
            uf = np.where(np.abs(uf) < 1.0, np.tan(np.pi / 4 * uf), uf)
            vf = np.where(np.abs(vf) < 1.0, np.tan(np.pi / 4 * vf), vf)
        else:
            uf, vf = np.tan(np.pi / 4 * uf), np.tan(np.pi / 4 * vf)
        d = (uf[..., None] * self._A[slot] + vf[..., None] * self._B[slot] + self._C[slot])
        d /= np.sqrt(uf * uf + vf * vf + 1.0)[..., None]
        return clean(d, ok, inplace=True)

    def pixel_kernel(self):
        """The compiled ``dir -> pixel`` (``eac_pixels``: the steps of :meth:`_dir_to_pixel`, its arc tangents to a
        few ulps), or None for a subclass that changed one of those steps."""
        from lenslab.lenses.core.native import kernel_holds, lens_kernels

        if not kernel_holds(self, EquiAngularCubemap, ("_dir_to_pixel",)):
            return None
        slot = self._slot_of_axis  # per major axis +x, -x, +y, -y, +z, -z: its face's slot, A and B as components
        faces = np.stack([slot % 3, slot // 3, self._iA.take(slot), self._sA.take(slot), self._iB.take(slot),
                          self._sB.take(slot)], axis=-1)
        fx_max = 1.0 - BORDER_NUDGE / (self.width * (1.0 - 2.0 * self.pu) / 3.0)
        fy_max = 1.0 - BORDER_NUDGE / (self.height * (0.5 - 2.0 * self.pv))
        return PixelKernel(lens_kernels().eac_pixels, np.concatenate(
            [[self.width, self.height, self.pu, self.pv, self.edge_slack, fx_max, fy_max], faces.ravel()]).astype(FLOAT))

    def dir_to_pixel(self, dirs):
        from lenslab.lenses.core.native import dir_to_pixel_through

        return dir_to_pixel_through(self, dirs, self._dir_to_pixel)

    def _dir_to_pixel(self, d):
        a = np.abs(d)
        axis = np.argmax(a, axis=-1)
        neg = np.take_along_axis(d, axis[..., None], axis=-1)[..., 0] < 0
        slot = self._slot_of_axis.take(2 * axis + neg)
        t = np.take_along_axis(a, axis[..., None], axis=-1)[..., 0]  # d . C > 0
        # A and B are signed unit axes: d . A is one component of d times a sign (divided by t, not multiplied
        # by 1 / t, which overflows for a subnormal t)
        uf = np.take_along_axis(d, self._iA.take(slot)[..., None], axis=-1)[..., 0]
        uf *= self._sA.take(slot)
        uf /= t
        vf = np.take_along_axis(d, self._iB.take(slot)[..., None], axis=-1)[..., 0]
        vf *= self._sB.take(slot)
        vf /= t
        fx = (4.0 / np.pi) * np.arctan(uf)
        fx += 1.0
        fx *= 0.5
        fy = (4.0 / np.pi) * np.arctan(vf)
        fy += 1.0
        fy *= 0.5
        col = slot % 3
        row = slot // 3
        fx = np.minimum(fx, 1.0 - BORDER_NUDGE / (self.width * (1.0 - 2.0 * self.pu) / 3.0))
        fy = np.minimum(fy, 1.0 - BORDER_NUDGE / (self.height * (0.5 - 2.0 * self.pv)))
        xy = np.empty(d.shape[:-1] + (2,), dtype=FLOAT)
        xy[..., 0] = self.width * (self.pu + (col + fx) * (1.0 - 2.0 * self.pu) / 3.0)
        xy[..., 1] = self.height * (self.pv + 0.5 * row + fy * (0.5 - 2.0 * self.pv))
        valid = (t > 0) & np.isfinite(t) & self.snap_to_image(xy)
        return clean(xy, valid, inplace=True)
