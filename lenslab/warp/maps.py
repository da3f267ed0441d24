"""Sampling maps: where each output sample reads the source, computed in float64.

For every output sample at continuous pixel position ``p`` (pixel centres at +0.5)::

    d_dst = dst.lens.pixel_to_dir(p)          # camera space of the output
    d_src = R d_dst,  R = R_src^T R_dst        # into the source's camera space
    q     = src.lens.dir_to_pixel(d_src)       # continuous source pixel position

and the sample is valid where both steps are. Samplers take *index* coordinates ``q - 0.5`` (the
centre of source pixel ``(i, j)`` at ``(i, j)``), stored as float32: at 16384 pixels float32 still
resolves 1/1000 of a pixel.

Evaluating the lens models for every output sample is the costly part of a warp, so by default the
map is evaluated exactly on a lattice of nodes every ``step`` output pixels and interpolated in
between (bicubic Catmull-Rom, in float64, the seam unwrapped). A lattice cell is interpolated only
where that is safe: its 4 corners are valid, its 16 stencil nodes have values (invalid nodes just
outside the valid region get extrapolated ghost values) and the interpolation agrees with the exact map
at four interior check points (t = 1/4, 3/4 on each axis) to within ``tol`` source pixels (default
1/500; the largest error measured anywhere in such cells is about 1/350, checked at every pixel by the
tests to 1/200, and to 1/50 near singular points). Errors are measured on the sphere: an error in x
counts as much as the source lens's ``column_scale`` says (a full-sphere panorama's columns crowd
together toward the poles: cos(latitude)), in units of the source's row height.

For a source whose seams have a pole, a cell that fails (near the pole, where x is singular) gets a
second chance: the ray *direction* is interpolated instead (smooth there) and projected exactly by the
source lens. A cell whose 16 nodes and check points all lie where the output lens has no ray
(outside a circular image) is empty. Every other cell (the rim of a circular image, a fold of a lens
model, a strongly curved map) is computed exactly, sample by sample; so are cameras made of pieces
(the lens's ``pieces``), whose maps jump between tiles and faces. ``exact=True`` skips the lattice
altogether.
"""

from __future__ import annotations

import functools
import warnings
from dataclasses import dataclass

import numpy as np

from lenslab.errors import WarpError
from lenslab.lenses import Camera, rotation_between, sample_offsets
from lenslab.lenses.core.native import project_kernel
from lenslab.warp.kernels.dispatch import run_bands, scratch
from lenslab.warp.lattice import (NEED_EXACT, NEED_PROJECT, cell_coefficients, exact_grids, ghost_nodes_into,
                                  lattice_eval, lattice_grid, lattice_rows, outside_field, place)

LATTICE_STEP = 8  # output pixels between lattice nodes
#: where each lattice cell's interpolation is checked against the exact map (fractions of the cell)
CHECK_POINTS = ((0.25, 0.25), (0.75, 0.25), (0.25, 0.75), (0.75, 0.75))
LATTICE_TOL = 2e-3  # source pixels: the largest interpolation error a lattice cell may show at its checks


class ParallaxWarning(UserWarning):
    """A view from an eye point other than the source's was warped anyway (allow_parallax=True)."""


def world_eyes(camera: Camera) -> np.ndarray:
    """The distinct eye points (world space) a camera's rays start from, shape (n, 3)."""
    offsets = np.asarray(camera.lens.eye_offsets, dtype=np.float64).reshape(-1, 3)
    return camera.pose.eye + offsets @ camera.pose.rotation.T


def check_eyes(src: Camera, dst: Camera, allow_parallax: bool = False) -> float:
    """Check that every ray of ``dst`` starts at the source's eye; return the largest distance.

    A panorama records the light arriving at one point. A view from another point (a tile of a
    multi-view camera at its own position) would show near objects shifted against far ones
    (parallax), which no reprojection of that panorama can recreate: that is a :class:`WarpError`,
    or a :class:`ParallaxWarning` with ``allow_parallax=True`` (every ray is then treated as leaving
    from the source's eye).
    """
    se, de = world_eyes(src), world_eyes(dst)
    scale = 1.0 + max(float(np.abs(se).max()), float(np.abs(de).max()))
    gap = float(np.max(np.linalg.norm(de[:, None, :] - se[None, :, :], axis=-1)))
    if gap <= 1e-9 * scale:
        return 0.0
    msg = (
        f"the output camera sees from {len(de)} eye point(s) up to {gap:.6g} away from the source's eye "
        f"{tuple(round(float(v), 6) for v in se[0])}: a panorama records the light arriving at one point, so a "
        "view from anywhere else would need parallax (near objects shift against far ones) that no "
        "reprojection can recreate. Render such views with the tracer or give one source image per eye; "
        "to warp anyway, as if every eye were at the source's (allow_parallax=True, --allow-parallax)"
    )
    if len(se) > 1 and gap > 1e-9 * scale:
        msg = "the source camera has several eye points; " + msg
    if not allow_parallax:
        raise WarpError(msg)
    warnings.warn(msg.replace("to warp anyway, as if", "warping anyway, as if"), ParallaxWarning, stacklevel=3)
    return gap


def exact_map(src: Camera, dst: Camera, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Where output positions read the source: the lens models evaluated in float64, no lattice.

    Parameters
    ----------
    src, dst : lenslab.lenses.Camera
        The source and output cameras.
    points : numpy.ndarray
        ``(..., 2)`` continuous pixel positions of ``dst`` (pixel centres at ``k + 1/2``).

    Returns
    -------
    xy : numpy.ndarray
        float64 ``(..., 2)`` source pixel positions (0 where invalid).
    valid : numpy.ndarray
        bool ``(...)``: the output has a ray there and the source sees it.

    Examples
    --------
    The centre of a forward 90-degree view reads an equirect panorama at its centre, and a view
    turned 90 degrees right reads it a quarter of the width further right:

    >>> import numpy as np, lenslab
    >>> from lenslab.warp import exact_map
    >>> from lenslab.lenses.projections.equirect import Equirect
    >>> from lenslab.lenses.projections.perspective import Perspective
    >>> pano = lenslab.Camera(Equirect(360, 180))
    >>> view = lenslab.Camera(Perspective(64, 64, fov=90))
    >>> from lenslab.lenses import Pose
    >>> right = lenslab.Camera(Perspective(64, 64, fov=90), Pose.from_ypr(90, 0, 0))
    >>> xy, ok = exact_map(pano, view, np.array([[32.0, 32.0]]))
    >>> xy.tolist(), ok.tolist()
    ([[180.0, 90.0]], [True])
    >>> exact_map(pano, right, np.array([[32.0, 32.0]]))[0].round(9).tolist()
    [[270.0, 90.0]]
    """
    xy, valid, _ = exact_map_parts(src, dst, points)
    return xy, valid


def exact_map_parts(src: Camera, dst: Camera, points: np.ndarray, with_dirs: bool = False):
    """Like :func:`exact_map`, plus whether the output ray itself exists (``dst`` validity alone)
    and, with ``with_dirs``, the ray directions in the source's camera space."""
    d, valid_dst = dst.lens.pixel_to_dir(points)
    r = rotation_between(src, dst)
    if not np.array_equal(r, np.eye(3)):
        d = d @ r.T
    xy, valid_src = project(src.lens, d)  # zero where invalid (a zero direction is invalid)
    if with_dirs:
        return xy, valid_dst & valid_src, valid_dst, d
    return xy, valid_dst & valid_src, valid_dst


#: directions below which :func:`project` calls the lens's vectorised ``dir_to_pixel`` even where the lens
#: has a compiled kernel (a few points: the same either way). The kernels are C++ (nothing to compile on first
#: use); an equirect's runs atan2 and hypot four at a time (glibc's vector maths): 19 ns against NumPy's 65 ns
#: per direction (6e4 directions, one thread, CPU time on a loaded machine); the two agree to a few ulps
#: (tests/warp/test_warp_project.py). The lattice's nodes, checks and the samples it leaves (rim, poles) are
#: projected in calls of thousands. Models whose ``dir_to_pixel`` is itself the kernel (perspective, Hammer,
#: cube maps, fisheye, little planet, cylinders, Brown pinhole, tiled grids of the first two) run it at every size.
COMPILED_PROJECT_MIN = 1 << 12


def project(lens, d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``lens.dir_to_pixel(d)``, through the lens's compiled kernel when it has one and ``d`` holds at
    least :data:`COMPILED_PROJECT_MIN` directions (float64 (..., 2))."""
    kern = lens.pixel_kernel() if np.size(d) >= 3 * COMPILED_PROJECT_MIN else None
    if kern is None:
        return lens.dir_to_pixel(d)
    return project_kernel(kern, d)


@dataclass
class MapBand:
    """The map of output rows ``r0:r1``: source index coordinates (float32) and validity per sample."""

    r0: int
    r1: int
    xs: np.ndarray  # (h, W, S) float32, source column index (centre of column i at i)
    ys: np.ndarray  # (h, W, S) float32
    valid: np.ndarray  # (h, W, S) bool

    @property
    def nbytes(self) -> int:
        return self.xs.nbytes + self.ys.nbytes + self.valid.nbytes


def wrap_width(src: Camera) -> float:
    """Period of the source's x coordinate in pixels (0: no wrap), as the source lens states it."""
    return float(src.lens.seams().period_x)


def piecewise(camera: Camera) -> bool:
    """Whether a camera's image is made of pieces (faces, tiles) whose map jumps at their edges."""
    return len(camera.lens.pieces()) > 1


class Mapper:
    """Computes maps from ``dst`` output positions into ``src`` pixels, band by band.

    ``offsets`` are the sub-pixel sample positions: shape ``(S, 2)`` (the same in every pixel) or
    ``(h, W, S, 2)`` per band (jittered); see :meth:`map_band`.
    """

    def __init__(self, src: Camera, dst: Camera, exact: bool = False, step: int = LATTICE_STEP,
                 tol: float = LATTICE_TOL):
        self.src, self.dst = src, dst
        self.width, self.height = dst.size
        self.wrap = wrap_width(src)
        self.step = int(step)
        self.tol = float(tol)
        # a source with a pole (where its x is singular) may interpolate the ray direction instead
        self.sphere = src.lens.seams().has_pole
        self.lattice = None
        if not exact and not piecewise(src) and not piecewise(dst) and self.width * self.height >= 16 * self.step * self.step:
            self.lattice = self._build_lattice()

    # -- lattice ---------------------------------------------------------------------------
    def _build_lattice(self):
        s = self.step
        ncx = -(-self.width // s)
        ncy = -(-self.height // s)
        xn = (np.arange(ncx + 3, dtype=np.float64) - 1.0) * s
        yn = (np.arange(ncy + 3, dtype=np.float64) - 1.0) * s
        # the exact map at the nodes and at the four check points of every cell, in chunks shared by the threads
        checks = [((np.arange(ncx) + tx) * s, (np.arange(ncy) + ty) * s, False) for tx, ty in CHECK_POINTS]
        # a source with a field bound: the nodes first, then the checks of the cells not wholly outside it
        field = self.src.lens.field()
        exact = exact_grids(self._exact_parts, [(xn, yn, True)] + ([] if field else checks))
        xy, v, vd, dirs = exact[0]
        outside = outside_field(field, dirs, vd, v)
        if outside is not None:
            exact += exact_grids(self._exact_parts, checks, ~outside)
        # the nodes' components (x, y and, for a sphere, the direction) as planes of one array, filled in place
        stacked = np.empty((5 if self.sphere else 2,) + v.shape)
        nx, ny = stacked[0], stacked[1]
        have = ghost_nodes_into(xy[..., 0], xy[..., 1], v, self.wrap, nx, ny)
        def win4(m, reduce):
            """``reduce`` (np.logical_and or np.logical_or) over each 4x4 window of ``m``, as two passes of
            three element-wise operations (the same as reducing the windows themselves, much faster)."""
            rows = reduce(reduce(m[:, :-3], m[:, 1:-2]), reduce(m[:, 2:-1], m[:, 3:]))
            return reduce(reduce(rows[:-3], rows[1:-2]), reduce(rows[2:-1], rows[3:]))

        def corners(m):
            return m[1:-2, 1:-2] & m[2:-1, 1:-2] & m[1:-2, 2:-1] & m[2:-1, 2:-1]

        # a cell interpolates when its 4 corners are valid and its 16 stencil nodes have values
        # (invalid nodes just outside the valid region get extrapolated ghost values; the checks
        # below decide whether the result is good enough)
        ok = win4(have, np.logical_and) & corners(v)
        dead = ~win4(vd, np.logical_or)  # no output ray anywhere near
        nodes = stacked[:2]
        # check at four interior points of each cell (the centre alone is a blind spot: Catmull-Rom's
        # error is odd about it), the four on the engine's threads
        kept = None if outside is None else np.flatnonzero(~outside)  # (the checks of the others are invalid)

        def check(job):
            (tx, ty), (exy, ev, _) = job
            ix, iy = lattice_grid(nx, ny, tx, ty, self.wrap)
            if kept is None:
                return ev & self._close(ix, iy, exy)
            passed = np.zeros(ev.shape, bool)
            passed.reshape(-1)[kept] = ev.reshape(-1)[kept] & self._close(
                ix.reshape(-1)[kept], iy.reshape(-1)[kept], exy.reshape(-1, 2)[kept])
            return passed

        for passed, (_, _, evd) in zip(run_bands(list(zip(CHECK_POINTS, exact[1:])), check), exact[1:]):
            ok &= passed
            dead &= ~evd
        if outside is not None:
            dead |= outside
        state = np.where(ok, 1, np.where(dead, -1, 0)).astype(np.int8)
        cand = state == 0
        if self.sphere and cand.any():
            # second chance for the cells left near a pole: interpolate the ray direction (smooth
            # there) and project it exactly; only where the output rays exist
            # two components a call, the third beside a spare plane: two calls of equal cost on the threads
            spare = np.empty(vd.shape)
            gd = run_bands([(2, 3), (4, None)], lambda p: ghost_nodes_into(
                dirs[..., p[0] - 2], dirs[..., (p[1] or p[0]) - 2], vd, 0.0, stacked[p[0]],
                spare if p[1] is None else stacked[p[1]]))
            nodes = stacked
            ok_dir = (win4(gd[0], np.logical_and) & corners(vd))[cand]

            def check_dir(job):
                (tx, ty), (exy, ev, _) = job
                dx, dy = lattice_grid(nodes[2], nodes[3], tx, ty, 0.0)  # two components a call
                d = np.stack([dx[cand], dy[cand], lattice_grid(nodes[4], nodes[4], tx, ty, 0.0)[0][cand]], axis=-1)
                pxy, pv = project(self.src.lens, d)
                return ev[cand] & pv & self._close(pxy[..., 0], pxy[..., 1], exy[cand])

            for passed in run_bands(list(zip(CHECK_POINTS, exact[1:])), check_dir):
                ok_dir &= passed
            state.reshape(-1)[np.flatnonzero(cand)[ok_dir]] = 2
        return nodes, state

    def _exact_parts(self, pts, with_dirs):
        return exact_map_parts(self.src, self.dst, pts, with_dirs)

    def _close(self, ix, iy, exy) -> np.ndarray:
        """Interpolated positions within ``tol`` of the exact ones (measured on the sphere)."""
        dx = ix - exy[..., 0]
        if self.wrap:
            dx -= self.wrap * np.round(dx / self.wrap)
        dx *= self.src.lens.column_scale(exy[..., 1])  # measured on the sphere
        return (np.abs(dx) <= self.tol) & (np.abs(iy - exy[..., 1]) <= self.tol)

    def _coefficients(self, cb0: int, cb1: int, coef: np.ndarray | None = None) -> np.ndarray:
        """Bicubic coefficients of cell rows ``cb0:cb1``: ``(rows, ncx, K, 4, 4)``, ``c[.., k, b, a]`` of
        tx^a ty^b, for K = 2 components (x, y) or 5 (x, y and the direction) on a sphere source; only the cells
        that interpolate are written (and read), into ``coef`` when given."""
        nodes, state = self.lattice
        if coef is None:
            coef = np.empty(self._coefficient_shape(cb0, cb1))
        cell_coefficients(nodes, state, cb0, cb1, self.wrap, coef)
        return coef

    def _coefficient_shape(self, cb0: int, cb1: int) -> tuple[int, ...]:
        nodes, state = self.lattice
        return (cb1 - cb0, state.shape[1], nodes.shape[0], 4, 4)

    @property
    def lattice_fraction(self) -> float:
        """Fraction of the output's lattice cells that are interpolated (the rest is computed exactly)."""
        return 0.0 if self.lattice is None else float((self.lattice[1] > 0).mean())

    # -- bands -----------------------------------------------------------------------------
    def map_band(self, r0: int, r1: int, offsets: np.ndarray, out: tuple | None = None) -> MapBand:
        """The map of output rows ``r0:r1`` at sub-pixel ``offsets`` ((S, 2) or (h, W, S, 2), in [0, 1]), written
        into ``out`` = (xs, ys, valid) (float32, float32, bool ``(h, W, S)``) when given."""
        offsets = np.asarray(offsets, dtype=np.float64)
        if offsets.ndim == 2:
            offsets = offsets[None, None]
        h, w = r1 - r0, self.width
        n = offsets.shape[2]
        if out is None:
            out = (np.empty((h, w, n), np.float32), np.empty((h, w, n), np.float32), np.empty((h, w, n), np.bool_))
        xs, ys, valid = out
        if self.lattice is None:  # every sample exactly
            pts = np.empty((h, w, n, 2), dtype=np.float64)
            pts[..., 0] = np.arange(w, dtype=np.float64)[None, :, None] + offsets[..., 0]
            pts[..., 1] = np.arange(r0, r1, dtype=np.float64)[:, None, None] + offsets[..., 1]
            xy, v = exact_map(self.src, self.dst, pts)
            xs[...] = xy[..., 0] - 0.5
            ys[...] = xy[..., 1] - 0.5
            valid[...] = v
            xs[~v] = 0.0
            ys[~v] = 0.0
            return MapBand(r0, r1, xs, ys, valid)
        state = self.lattice[1]
        cb0 = max(0, int(np.floor((r0 + offsets[..., 1].min()) / self.step)))
        cb1 = min(state.shape[0], int(np.floor((r1 - 1 + offsets[..., 1].max()) / self.step)) + 1)
        # the band's working arrays are scratch, kept between bands and warps (their pages faulted in once)
        with scratch((h, w, n), np.int8) as need, \
                scratch((h, w, n, 3) if (state[cb0:cb1] == 2).any() else (1, 1, 1, 3)) as dirs, \
                scratch(self._coefficient_shape(cb0, cb1)) as coef:
            self._coefficients(cb0, cb1, coef)
            if offsets.shape[:2] == (1, 1):  # the same offsets in every pixel (the common case)
                lattice_rows(coef, state, cb0, 1.0 / self.step, r0, offsets, xs, ys, valid, need, dirs)
            else:
                lattice_eval(coef, state, cb0, float(self.step), r0, offsets, xs, ys, valid, need, dirs)
            rows = state[cb0:cb1]
            for code in (c for c, st in ((NEED_PROJECT, 2), (NEED_EXACT, 0)) if (rows == st).any()):
                flat = np.flatnonzero(need == code)
                if len(flat):
                    self.fill(flat, code, dirs, offsets, r0, need.shape, xs.reshape(-1), ys.reshape(-1),
                              valid.reshape(-1), flat)
        return MapBand(r0, r1, xs, ys, valid)

    def fill(self, flat, code, dirs, offsets, r0, shape, xs, ys, valid, at) -> None:
        """Map the samples at flat positions ``flat`` of a band of ``shape`` (h, W, S) that the lattice
        left: by their interpolated direction (``NEED_PROJECT``, projected by the source lens) or
        exactly (``NEED_EXACT``); write their index coordinates and validity at ``at`` of the flat
        arrays ``xs``, ``ys``, ``valid``."""
        if code == NEED_PROJECT:
            xy, v = project(self.src.lens, np.take(dirs.reshape(-1, 3), flat, axis=0))
        else:
            r, c, k = np.unravel_index(flat, shape)
            if offsets.shape[:2] == (1, 1):  # the same offsets in every pixel: no gather over pixels
                o = offsets[0, 0, 0] if offsets.shape[2] == 1 else np.take(offsets[0, 0], k, axis=0)
            else:
                o = offsets[r % offsets.shape[0], c % offsets.shape[1], k]
            pts = np.empty((len(flat), 2))
            np.add(c, o[..., 0], out=pts[:, 0])
            np.add(r0 + r, o[..., 1], out=pts[:, 1])
            xy, v = exact_map(self.src, self.dst, pts)
        place(at, xy.reshape(-1, 2), v.reshape(-1), xs, ys, valid)


def sample_pattern(samples: int) -> np.ndarray:
    """Fixed stratified sub-pixel offsets, shape (S, 2): strata centres of a k x k grid (or n-rooks); read-only, made
    once per count (every band of a warp asks for them)."""
    return _pattern(int(samples))


@functools.lru_cache(maxsize=64)
def _pattern(samples: int) -> np.ndarray:
    offsets = sample_offsets(samples, (), None)
    offsets.setflags(write=False)
    return offsets
