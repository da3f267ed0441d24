"""Anti-aliasing by footprint: average the source over the region each output pixel covers.

Where the output shrinks the source (a wide-angle view of a detailed panorama, the rows near a pole),
one bilinear tap per pixel skips most of the source and small bright features (the sun) flicker in
and out. Supersampling (``samples=N``) fixes it at N times the cost everywhere. The footprint
prefilter spends the work only where it is needed:

1. The local Jacobian of the map gives the pixel's footprint on the source, a parallelogram spanned
   by ``a`` and ``b`` (in source pixels, the seam unwrapped). At one sample per pixel they are
   central differences of the map between the neighbouring pixels, ``a = (q(p + (1, 0)) -
   q(p - (1, 0))) / 2`` (one-sided beside an invalid neighbour, the image's border or the edge of a
   piece of a piecewise output: a cube map's faces, a barrel's band and caps, of any sizes), so the
   footprint costs no map evaluations beyond the pixel centres. Combined
   with ``samples``, they are secants across each sub-sample's stratum, ``a = q(p + (h, 0)) -
   q(p - (h, 0))`` with ``h`` half the stratum's side, their ends kept inside the piece of the
   sample.
2. A box-filtered pyramid of the source (each level halves the previous by 2x2 averaging; the seam
   and pole structure of a panorama survives the halving; :mod:`lenslab.warp.pyramid`) provides pre-averaged texels.
3. The level ``L`` is the finest at which the footprint spans at most ``MAX_TAPS`` texels along its
   longer side (a coarser level blurs: its texels are 2x2 means read bilinearly).
4. The bilinear reconstruction is integrated over the parallelogram by Green's theorem: the integral
   over y of F at the right ends of its rows less F at the left ends, where F(x, y) is the integral of
   the reconstruction along row y up to x (the parallelogram is taken along its shorter extent: rows,
   or columns for a tall one). Along each texel row F is a running sum of trapezoids plus a quadratic
   inside the last one, read in O(1) from the prefix sums of the window's rows, whatever the
   footprint's width. Each edge is cut at the texel rows (where the reconstruction bends in y) and
   each piece integrated by 2-point Gauss-Legendre, exact while the edge stays between two texel
   columns (``src/native/footprint_edges.h``; ``tests/warp/test_footprint_exact.py`` bounds the error
   where it crosses one). The integral is divided by the parallelogram's area.
5. A pixel whose validity differs from a neighbour's (or, on the image's border, from the point half
   a pixel outside) straddles the edge of the valid region (a circular image's rim, a source image's
   border): it is split into ``EDGE_SPLIT x EDGE_SPLIT`` sub-samples mapped exactly, which measure its
   partial coverage. Each valid sub-sample is itself a footprint, the sample's sides divided by
   ``EDGE_SPLIT``, so a lamp on the rim is averaged over each sub-cell, not read at its centre.

The result approximates the box average of the bilinear reconstruction over the pixel, which is what
dense supersampling converges to; ``lenslab bench warp`` measures the difference on real panoramas.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from lenslab.warp.kernels import native
from lenslab.warp.kernels.native import c32, cbool
from lenslab.warp.maps import MapBand, Mapper, exact_map
from lenslab.warp.minification import watch
from lenslab.warp.pyramid import MAX_TAPS, pyramid, sample_footprint  # noqa: F401  (the source side)

#: a footprint is kept at least this many source pixels thick (and at least 1/SLIVER_ANISOTROPY of its longer side,
#: when that is less). A sliver (sides almost parallel: a strong swirl's, near where its map folds) has an area far
#: smaller than its sides, and the integral over it, exact to a small absolute error, divided by that area made
#: values far outside the source's range (negative ones from a positive panorama); half a pixel bounds it and
#: brings the swirl of a real panorama closer to 256-sample supersampling (city.exr: relative L1 0.25% -> 0.16%)
SLIVER_HEIGHT = 0.5
SLIVER_ANISOTROPY = 8.0
JACOBIAN_POINTS = 5  # map evaluations per sample with samples > 1: the centre and the four secant ends
EDGE_SPLIT = 4  # a sample whose footprint straddles the edge of the valid region becomes EDGE_SPLIT^2 samples


@dataclass
class FootprintBand(MapBand):
    """A map band with each sample's footprint: ``foot[..., 0:2]`` = a, ``foot[..., 2:4]`` = b (source px)."""

    foot: np.ndarray = None  # (h, W, S, 4) float32
    edge: np.ndarray = None  # (h, W, S) bool: the sample straddles the edge of the valid region
    edge_idx: np.ndarray = None  # (M,) flat indices of the edge samples into (h, W, S)
    edge_xs: np.ndarray = None  # (M, K) float32: their sub-samples (index coordinates)
    edge_ys: np.ndarray = None
    edge_valid: np.ndarray = None  # (M, K) bool
    #: (N,) int64 flat indices into (h, W, S), in order, of the valid samples whose footprint may span more than
    #: MAX_TAPS texels (so may read the pyramid's coarser levels): a superset of those that do; None: not known
    coarse: np.ndarray = None

    @property
    def nbytes(self) -> int:
        return (super().nbytes + self.foot.nbytes + self.edge.nbytes + self.edge_idx.nbytes
                + self.edge_xs.nbytes + self.edge_ys.nbytes + self.edge_valid.nbytes
                + (0 if self.coarse is None else self.coarse.nbytes))


def draw_footprints(plan, pyr, band: "FootprintBand", out: np.ndarray, alpha: np.ndarray) -> None:
    """Fill ``out`` and ``alpha`` for a footprint band of ``plan`` from the source's pyramid ``pyr``, its footprints
    looked at on the way (:func:`lenslab.warp.minification.watch`: whether the plan shrinks its source anywhere)."""
    watch(plan, band)
    sample_footprint(pyr, band, plan.border, out, alpha)


def footprint_band(mapper: Mapper, r0: int, r1: int, offsets: np.ndarray) -> FootprintBand:
    """The map of rows ``r0:r1`` at ``offsets`` plus every sample's footprint on the source."""
    offsets = np.asarray(offsets, dtype=np.float64)
    if offsets.ndim == 2:
        offsets = offsets[None, None]
    n = offsets.shape[2]
    half = 0.5 / max(1.0, np.sqrt(n))  # half the side of one sample's stratum
    h, w = r1 - r0, mapper.width
    if offsets.shape[:3] == (1, 1, 1):  # one sample per pixel: secants between neighbouring pixels
        return _split_edges(mapper, r0, offsets, half, *_neighbour_footprint(mapper, r0, r1, offsets))
    # centre, then -x, +x, -y, +y; the lattice/exact map handles each shifted set like any samples
    shifts = np.array([[0, 0], [-half, 0], [half, 0], [0, -half], [0, half]], dtype=np.float64)
    allo = (offsets[..., None, :, :] + shifts[:, None, :]).reshape(offsets.shape[:2] + (5 * n, 2))
    rects = piece_rects(mapper.dst.lens)
    if rects is not None:
        allo = _inside_piece(allo, offsets, r0, h, w, rects)
    band = mapper.map_band(r0, r1, allo)
    xs = band.xs.reshape(h, w, 5, n)
    ys = band.ys.reshape(h, w, 5, n)
    vs = band.valid.reshape(h, w, 5, n)
    foot = np.empty((h, w, n, 4), dtype=np.float32)
    secants(xs, ys, vs, mapper.wrap, foot)
    # samples whose five points disagree on validity straddle the edge of the valid region (a
    # circular image's rim, a source image's border): their coverage is partial, so they are split into
    # EDGE_SPLIT x EDGE_SPLIT plain sub-samples that measure it
    edge = vs.any(axis=2) & ~vs.all(axis=2)
    return _split_edges(mapper, r0, offsets, half, np.ascontiguousarray(xs[:, :, 0]),
                        np.ascontiguousarray(ys[:, :, 0]), np.ascontiguousarray(vs[:, :, 0]), foot, edge)


def _neighbour_footprint(mapper: Mapper, r0: int, r1: int, offsets: np.ndarray):
    """Map and footprint of rows ``r0:r1`` at one sample per pixel, from the map at the pixel centres
    alone: the footprint's sides are central differences between the neighbouring pixels (one-sided
    beside an invalid neighbour, the image's edge or a seam of a piecewise output such as a cube
    map's faces), the map of one more row above and below the band included. A pixel is on the edge
    of the valid region when a neighbour's validity differs from its own."""
    h, w = r1 - r0, mapper.width
    a0, a1 = max(0, r0 - 1), min(mapper.height, r1 + 1)
    band = mapper.map_band(a0, a1, offsets)
    rects = piece_rects(mapper.dst.lens)
    piece = None
    if rects is not None:  # the piece of each pixel centre of the rows mapped
        piece = piece_numbers(rects, np.arange(w)[None, :] + 0.5, np.arange(a0, a1)[:, None] + 0.5)
    foot = np.empty((h, w, 1, 4), dtype=np.float32)
    edge = np.empty((h, w, 1), dtype=np.bool_)
    coarse = neighbour_secants(band.xs[..., 0], band.ys[..., 0], band.valid[..., 0], r0 - a0, mapper.wrap, piece,
                               foot, edge, far=MAX_TAPS)
    top = r0 - a0
    valid = band.valid[top:top + h]
    # pixels on the image's border have no neighbour outside it: the validity of the point half a
    # pixel outside (mapped exactly) tells whether the edge of the valid region passes there
    rr, cc, dx, dy = [], [], [], []
    rows = np.arange(h)
    for col, step in ((0, -0.5), (w - 1, 0.5)):
        rr.append(rows), cc.append(np.full(h, col)), dx.append(np.full(h, step)), dy.append(np.zeros(h))
    for row, step in ((0, -0.5), (mapper.height - 1, 0.5)):
        if r0 <= row < r1:
            rr.append(np.full(w, row - r0)), cc.append(np.arange(w)), dx.append(np.zeros(w))
            dy.append(np.full(w, step))
    rr, cc, dx, dy = (np.concatenate(v) for v in (rr, cc, dx, dy))
    o = offsets[0, 0, 0]
    _, ok = exact_map(mapper.src, mapper.dst, np.stack([cc + o[0] + dx, r0 + rr + o[1] + dy], axis=-1))
    edge[rr[ok != valid[rr, cc, 0]], cc[ok != valid[rr, cc, 0]], 0] = True
    return (band.xs[top:top + h], band.ys[top:top + h], valid, foot, edge, coarse)


def thicken_slivers(foot: np.ndarray) -> bool:
    """Widen in place every footprint (``foot[..., 0:2]`` = a, ``[..., 2:4]`` = b) thinner than
    ``min(SLIVER_HEIGHT, longer side / SLIVER_ANISOTROPY)`` across its longer side to that height, by moving its
    shorter side along the longer one's normal (the orientation kept). Returns whether any was widened."""
    flat = foot.reshape(-1, 4)
    # |a x b| / longer side < min(SLIVER_HEIGHT, longer side / SLIVER_ANISOTROPY), squared, in float32: the
    # squared cross product against min(long2 SLIVER_HEIGHT^2, long2^2 / SLIVER_ANISOTROPY^2), long2 the longer
    # side squared (one compiled pass; reference :func:`thin_reference`)
    thin = np.empty(len(flat), np.int64)  # (pages get memory only where written: a few here)
    thin = thin[:native.kernels().thin_footprints(c32(flat), np.float32(SLIVER_HEIGHT ** 2),
                                                  np.float32(SLIVER_ANISOTROPY ** 2), thin)]
    if not len(thin):
        return False
    f = flat[thin].astype(np.float64)
    a, b = f[:, 0:2], f[:, 2:4]
    a_long = (a * a).sum(axis=1) >= (b * b).sum(axis=1)
    longer = np.where(a_long[:, None], a, b)
    length = np.hypot(longer[:, 0], longer[:, 1])
    cross = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    sign = np.where(cross >= 0.0, 1.0, -1.0)
    height = np.minimum(SLIVER_HEIGHT, length / SLIVER_ANISOTROPY)
    add = (height * length - np.abs(cross)) / np.maximum(length, 1e-30)  # height to add
    normal = np.stack([-longer[:, 1], longer[:, 0]], axis=1) / np.maximum(length, 1e-30)[:, None]
    step = (sign * add)[:, None] * normal  # a x (b + step) = cross + sign * add * length; (a - step) x b too
    f[:, 2:4] = np.where(a_long[:, None], b + step, b)
    f[:, 0:2] = np.where(a_long[:, None], a, a - step)
    flat[thin] = f
    return True


def thin_reference(foot: np.ndarray) -> np.ndarray:
    """The flat indices of the footprints (``(..., 4)`` float32) that :func:`thicken_slivers` widens, in NumPy's
    float32 steps (the reference of the compiled ``thin_footprints``)."""
    a0, a1, b0, b1 = foot.reshape(-1, 4).T
    long2 = np.maximum(a0 * a0 + a1 * a1, b0 * b0 + b1 * b1)
    cross = a0 * b1
    cross -= a1 * b0
    cross *= cross
    return np.flatnonzero(cross < np.minimum(long2 * np.float32(SLIVER_HEIGHT ** 2),
                                             long2 * long2 / np.float32(SLIVER_ANISOTROPY ** 2)))


def _split_edges(mapper: Mapper, r0: int, offsets, half: float, xs, ys, valid, foot, edge,
                 coarse=None) -> "FootprintBand":
    """The footprint band, with the samples on the edge of the valid region split into
    EDGE_SPLIT x EDGE_SPLIT plain sub-samples (mapped exactly) that measure their partial coverage. Slivers are
    widened first (:func:`thicken_slivers`); a widened side may reach a coarser level, so then every sample is
    looked at for it (``coarse`` None)."""
    if thicken_slivers(foot):
        coarse = None
    flat = np.flatnonzero(edge)
    k = EDGE_SPLIT
    sub = ((np.arange(k) + 0.5) / k - 0.5) * (2.0 * half)
    sub = np.stack(np.meshgrid(sub, sub, indexing="xy"), axis=-1).reshape(-1, 2)  # (K, 2)
    rr, cc, ss = np.unravel_index(flat, edge.shape)
    o = offsets[rr % offsets.shape[0], cc % offsets.shape[1], ss]  # (M, 2)
    pts = np.empty((len(flat), k * k, 2))
    pts[..., 0] = (cc + o[:, 0])[:, None] + sub[None, :, 0]
    pts[..., 1] = (r0 + rr + o[:, 1])[:, None] + sub[None, :, 1]
    exy, ev = exact_map(mapper.src, mapper.dst, pts)
    return FootprintBand(r0, r0 + xs.shape[0], np.ascontiguousarray(xs), np.ascontiguousarray(ys),
                         np.ascontiguousarray(valid), foot, edge, flat,
                         (exy[..., 0] - 0.5).astype(np.float32), (exy[..., 1] - 0.5).astype(np.float32), ev,
                         coarse)


def piece_rects(lens):
    """``(N, 4)`` float64 rectangles ``(x0, y0, width, height)`` of an output lens made of two or more
    pieces (cube faces, the halves of a double image, the band and caps of a barrel), so that its map
    jumps at their edges; else None. The pieces may differ in size and lie anywhere."""
    pieces = lens.pieces()
    if len(pieces) < 2:
        return None
    return np.array([p.rect for p in pieces], dtype=np.float64)


def piece_numbers(rects, px, py) -> np.ndarray:
    """int32 number of the piece (row of ``rects``) holding each point ``(px, py)`` (continuous pixels);
    -1 for a point in none. Where pieces overlap, the first one listed holds the point."""
    px, py = np.broadcast_arrays(np.asarray(px, dtype=np.float64), np.asarray(py, dtype=np.float64))
    out = np.full(px.shape, -1, dtype=np.int32)
    for k in range(len(rects) - 1, -1, -1):
        x0, y0, pw, ph = rects[k]
        out[(px >= x0) & (px < x0 + pw) & (py >= y0) & (py < y0 + ph)] = k
    return out


#: pixels by which a secant end is kept inside its piece (far below any map error that matters)
PIECE_INSET = 1e-6


def _inside_piece(allo, offsets, r0, h, w, rects):
    """Per-pixel sample positions (h, W, 5S, 2) with every secant end moved into the piece (cube face)
    of its sample: a footprint is measured inside the piece it belongs to, never across a seam."""
    n = offsets.shape[2]
    cx = np.arange(w, dtype=np.float64)[None, :, None]
    cy = np.arange(r0, r0 + h, dtype=np.float64)[:, None, None]
    centre = np.broadcast_to(offsets, (h, w, n, 2))
    k = piece_numbers(rects, cx + centre[..., 0], cy + centre[..., 1])  # (h, W, S)
    box = np.where((k >= 0)[..., None], rects[np.maximum(k, 0)], [[-np.inf, -np.inf, np.inf, np.inf]])
    x0, y0 = box[..., 0][:, :, None], box[..., 1][:, :, None]
    x1, y1 = x0 + box[..., 2][:, :, None] - PIECE_INSET, y0 + box[..., 3][:, :, None] - PIECE_INSET
    ends = np.broadcast_to(allo, (h, w) + allo.shape[2:]).reshape(h, w, 5, n, 2).copy()
    ends[..., 0] = np.clip(cx[:, :, None] + ends[..., 0], x0, x1) - cx[:, :, None]
    ends[..., 1] = np.clip(cy[:, :, None] + ends[..., 1], y0, y1) - cy[:, :, None]
    return ends.reshape(h, w, 5 * n, 2)


def neighbour_secants(xs, ys, vs, top: int, wrap: float, piece, foot, edge, far: float | None = None):
    """Footprint sides of the pixels of rows ``top:top + h`` of a map of pixel centres (``xs`` etc.
    (rows, W)) from their neighbours, into ``foot`` (h, W, 1, 4) and ``edge`` (h, W, 1); ``piece`` (rows, W)
    int32 numbers each pixel's piece (None: one piece), and a neighbour in another piece does not count
    (compiled ahead of time; reference :func:`lenslab.warp.kernels.reference.neighbour_secants`).

    With ``far``: returns the int64 flat indices (into (h, W)) of the valid pixels with a side that may be longer
    than ``far`` texels (every one that is, and a few within a float32 rounding of it), found as the sides are made."""
    piece = np.zeros((0, 0), np.int32) if piece is None else np.ascontiguousarray(piece, dtype=np.int32)
    k = native.kernels()
    if far is None:
        k.neighbour_secants(c32(xs), c32(ys), cbool(vs), int(top), float(wrap), piece, foot, edge)
        return None
    idx = np.empty(edge.size, np.int64)  # pages are given memory only where written: about 2% of them here
    n = k.neighbour_secants(c32(xs), c32(ys), cbool(vs), int(top), float(wrap), piece, foot, edge, float(far), idx)
    return idx[:n].copy()


def secants(xs, ys, vs, wrap: float, foot) -> None:
    """Footprint sides of supersampled pixels into ``foot`` (h, W, S, 4) from the map ``xs, ys, vs`` (h, W, 5, S)
    at each sample and the ends of its two secants: the secant across the sample's stratum, one-sided (doubled)
    where an end is invalid (compiled ahead of time; reference :func:`lenslab.warp.kernels.reference.secants`)."""
    native.kernels().secants(c32(xs), c32(ys), cbool(vs), float(wrap), foot)
