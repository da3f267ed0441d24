"""Anti-aliasing by footprint: average the source over the region each output pixel covers.

Where the output shrinks the source (a wide fisheye from a detailed panorama, the rows near a pole),
one bilinear tap per pixel skips most of the source and small bright features (the sun) flicker in
and out. Supersampling (``samples=N``) fixes it at N times the cost everywhere. The footprint
prefilter spends the work only where it is needed:

1. The local Jacobian of the map gives the pixel's footprint on the source, a parallelogram spanned
   by ``a`` and ``b`` (in source pixels, the seam unwrapped). At one sample per pixel they are
   central differences of the map between the neighbouring pixels, ``a = (q(p + (1, 0)) -
   q(p - (1, 0))) / 2`` (one-sided beside an invalid neighbour, the image's border or a face seam of a
   cube-map output), so the footprint costs no map evaluations beyond the pixel centres. Combined
   with ``samples``, they are secants across each sub-sample's stratum, ``a = q(p + (h, 0)) -
   q(p - (h, 0))`` with ``h`` half the stratum's side, their ends kept inside the cube face of the
   sample.
2. A box-filtered pyramid of the source (each level halves the previous by 2x2 averaging; the seam
   and pole structure of an equirect survives the halving) provides pre-averaged texels.
3. The level ``L`` is the finest at which the footprint spans at most ``MAX_TAPS`` texels along its
   longer side. A footprint at most 3 texels wide and tall whose x-y covariance is about zero
   (``AXIS_TOL``) is read as one axis-aligned box with its second moments; any other is split into
   ``na x nb`` cells, about ``1/DENSITY`` texel each along ``a`` and ``b`` (anisotropic: a long thin
   footprint near a pole gets many cells along its length, few across).
4. Each cell is replaced by the axis-aligned box with the same second moments, and the bilinear
   reconstruction is averaged over that box exactly: separable weights, the tent integrated over the
   box (:func:`_tent_box_weights`). The cells' weights are summed in one window of texels, which is
   then read once.
5. A pixel whose validity differs from a neighbour's (or, on the image's border, from the point half
   a pixel outside) straddles the edge of the valid region (a fisheye's rim, a source image's
   border): it is split into ``EDGE_SPLIT x EDGE_SPLIT`` sub-samples mapped exactly, which measure its
   partial coverage.

The result approximates the box average of the bilinear reconstruction over the pixel, which is what
dense supersampling converges to; ``lenslab bench warp`` measures the difference on real panoramas.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numba
import numpy as np

from lenslab.warp.dispatch import kernel
from lenslab.warp.maps import MapBand, Mapper, exact_map
from lenslab.warp.seam import Border, fold_index

JACOBIAN_POINTS = 5  # map evaluations per sample with samples > 1: the centre and the four secant ends
EDGE_SPLIT = 4  # a sample whose footprint straddles the edge of the valid region becomes EDGE_SPLIT^2 samples
MAX_TAPS = 8.0  # longest side of a footprint, in texels of the level it is read from
AXIS_TOL = 0.125  # texels^2: a footprint whose x-y covariance (times 12) is below this is one box
DENSITY = 0.75  # cells per texel along each side of the footprint (measured best accuracy per cost)
WINDOW = 16  # texels: the side of the window of weights a footprint is gathered through (fits MAX_TAPS + 5)


@dataclass
class FootprintBand(MapBand):
    """A map band with each sample's footprint: ``foot[..., 0:2]`` = a, ``foot[..., 2:4]`` = b (source px)."""

    foot: np.ndarray = None  # (h, W, S, 4) float32
    edge: np.ndarray = None  # (h, W, S) bool: the sample straddles the edge of the valid region
    edge_idx: np.ndarray = None  # (M,) flat indices of the edge samples into (h, W, S)
    edge_xs: np.ndarray = None  # (M, K) float32: their sub-samples (index coordinates)
    edge_ys: np.ndarray = None
    edge_valid: np.ndarray = None  # (M, K) bool

    @property
    def nbytes(self) -> int:
        return (super().nbytes + self.foot.nbytes + self.edge.nbytes + self.edge_idx.nbytes
                + self.edge_xs.nbytes + self.edge_ys.nbytes + self.edge_valid.nbytes)


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
    pieces = _pieces(mapper.dst.lens)
    if pieces is not None:
        allo = _inside_piece(allo, offsets, r0, h, w, pieces)
    band = mapper.map_band(r0, r1, allo)
    xs = band.xs.reshape(h, w, 5, n)
    ys = band.ys.reshape(h, w, 5, n)
    vs = band.valid.reshape(h, w, 5, n)
    foot = np.empty((h, w, n, 4), dtype=np.float32)
    _secants(xs, ys, vs, mapper.wrap, foot, work=xs.size)
    # samples whose five points disagree on validity straddle the edge of the valid region (a
    # fisheye's rim, a source image's border): their coverage is partial, so they are split into
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
    pieces = _pieces(mapper.dst.lens) or (0.0, 0.0)
    foot = np.empty((h, w, 1, 4), dtype=np.float32)
    edge = np.empty((h, w, 1), dtype=np.bool_)
    _neighbour_secants(band.xs[..., 0], band.ys[..., 0], band.valid[..., 0], r0 - a0, a0, mapper.wrap,
                       float(pieces[0]), float(pieces[1]), foot, edge)
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
    return (band.xs[top:top + h], band.ys[top:top + h], valid, foot, edge)


def _split_edges(mapper: Mapper, r0: int, offsets, half: float, xs, ys, valid, foot, edge) -> "FootprintBand":
    """The footprint band, with the samples on the edge of the valid region split into
    EDGE_SPLIT x EDGE_SPLIT plain sub-samples (mapped exactly) that measure their partial coverage."""
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
                         (exy[..., 0] - 0.5).astype(np.float32), (exy[..., 1] - 0.5).astype(np.float32), ev)


def _pieces(lens):
    """``(piece width, piece height)`` of an output lens whose map jumps between pieces (a cube map's
    faces), else None."""
    if getattr(lens, "name", "") == "cubemap":
        return lens.face_size
    return None


#: pixels by which a secant end is kept inside its piece (far below any map error that matters)
PIECE_INSET = 1e-6


def _inside_piece(allo, offsets, r0, h, w, pieces):
    """Per-pixel sample positions (h, W, 5S, 2) with every secant end moved into the piece (cube face)
    of its sample: a footprint is measured inside the face it belongs to, never across a face seam."""
    fw, fh = pieces
    n = offsets.shape[2]
    cx = np.arange(w, dtype=np.float64)[None, :, None]
    cy = np.arange(r0, r0 + h, dtype=np.float64)[:, None, None]
    centre = np.broadcast_to(offsets, (h, w, n, 2))
    px = cx + centre[..., 0]  # (h, W, S) absolute sample positions
    py = cy + centre[..., 1]
    x0 = np.floor(px / fw) * fw
    y0 = np.floor(py / fh) * fh
    ends = np.broadcast_to(allo, (h, w) + allo.shape[2:]).reshape(h, w, 5, n, 2).copy()
    ends[..., 0] = np.clip(cx[:, :, None] + ends[..., 0], x0[:, :, None], x0[:, :, None] + fw - PIECE_INSET) \
        - cx[:, :, None]
    ends[..., 1] = np.clip(cy[:, :, None] + ends[..., 1], y0[:, :, None], y0[:, :, None] + fh - PIECE_INSET) \
        - cy[:, :, None]
    return ends.reshape(h, w, 5 * n, 2)


@numba.njit(cache=True, nogil=True)
def _neighbour_secants(xs, ys, vs, top, row0, wrap, piece_w, piece_h, foot, edge):
    """Footprint sides of the pixels of rows ``top:top + h`` of a map of pixel centres (``xs`` etc.
    (rows, W); the band's first row is image row ``row0 + top``) from their neighbours."""
    h, w = foot.shape[0], foot.shape[1]
    nrows = xs.shape[0]
    for r in range(h):
        rr = r + top
        prow = -1.0 if piece_h <= 0.0 else np.floor((row0 + rr + 0.5) / piece_h)
        for c in range(w):
            pcol = -1.0 if piece_w <= 0.0 else np.floor((c + 0.5) / piece_w)
            v0 = vs[rr, c]
            on_edge = False
            for axis in range(2):
                # the neighbours before and after along this axis, if inside the image and the piece
                if axis == 0:
                    lo_ok = c > 0 and (piece_w <= 0.0 or np.floor((c - 0.5) / piece_w) == pcol)
                    hi_ok = c + 1 < w and (piece_w <= 0.0 or np.floor((c + 1.5) / piece_w) == pcol)
                    rl, cl, rh, ch = rr, c - 1, rr, c + 1
                else:
                    lo_ok = rr > 0 and (piece_h <= 0.0 or np.floor((row0 + rr - 0.5) / piece_h) == prow)
                    hi_ok = rr + 1 < nrows and (piece_h <= 0.0 or np.floor((row0 + rr + 1.5) / piece_h) == prow)
                    rl, cl, rh, ch = rr - 1, c, rr + 1, c
                vl = lo_ok and vs[rl, cl]
                vh = hi_ok and vs[rh, ch]
                if (lo_ok and vs[rl, cl] != v0) or (hi_ok and vs[rh, ch] != v0):
                    on_edge = True
                half = 1.0
                if vl and vh:
                    dx = xs[rh, ch] - xs[rl, cl]
                    dy = ys[rh, ch] - ys[rl, cl]
                    half = 0.5
                elif vh and v0:
                    dx = xs[rh, ch] - xs[rr, c]
                    dy = ys[rh, ch] - ys[rr, c]
                elif vl and v0:
                    dx = xs[rr, c] - xs[rl, cl]
                    dy = ys[rr, c] - ys[rl, cl]
                else:
                    dx = 0.0
                    dy = 0.0
                if wrap > 0.0:  # unwrapped before halving: a difference across the seam is near +-wrap
                    dx -= wrap * np.floor(dx / wrap + 0.5)
                foot[r, c, 0, 2 * axis] = half * dx
                foot[r, c, 0, 2 * axis + 1] = half * dy
            edge[r, c, 0] = on_edge


@kernel
def _secants(xs, ys, vs, wrap, foot):
    h, w, _, n = xs.shape
    for r in range(h):
        for c in range(w):
            for k in range(n):
                for axis in range(2):
                    lo, hi = 1 + 2 * axis, 2 + 2 * axis
                    # secant across the stratum; one-sided (doubled) where an end is invalid
                    if vs[r, c, lo, k] and vs[r, c, hi, k]:
                        dx = xs[r, c, hi, k] - xs[r, c, lo, k]
                        dy = ys[r, c, hi, k] - ys[r, c, lo, k]
                    elif vs[r, c, hi, k] and vs[r, c, 0, k]:
                        dx = 2.0 * (xs[r, c, hi, k] - xs[r, c, 0, k])
                        dy = 2.0 * (ys[r, c, hi, k] - ys[r, c, 0, k])
                    elif vs[r, c, lo, k] and vs[r, c, 0, k]:
                        dx = 2.0 * (xs[r, c, 0, k] - xs[r, c, lo, k])
                        dy = 2.0 * (ys[r, c, 0, k] - ys[r, c, lo, k])
                    else:
                        dx = 0.0
                        dy = 0.0
                    if wrap > 0.0:
                        dx -= wrap * np.floor(dx / wrap + 0.5)
                    foot[r, c, k, 2 * axis] = dx
                    foot[r, c, k, 2 * axis + 1] = dy


@dataclass
class Pyramid:
    """Box-filtered levels of a source: level 0 is the source itself, the others packed in one buffer."""

    level0: np.ndarray  # the source, flattened (a view, no copy)
    rest: np.ndarray  # levels 1.. one after the other, flattened float32
    shapes: np.ndarray  # (L, 2) int64: (height, width) of each level
    offsets: np.ndarray  # (L,) int64: start of each level in ``rest`` (0 for level 0)
    channels: int
    source: np.ndarray  # the source, H x W x C


def pyramid(src: np.ndarray, border: Border) -> Pyramid:
    """Box-filtered levels of ``src``: level 0 is ``src``, each next one halves it (2x2 mean).

    Halving stops at a level with an odd side (its seam or pole structure would shift by half a texel)
    or below 2 pixels. The extra levels take a third of the source's memory.
    """
    levels = []
    cur = src
    while cur.shape[0] >= 2 and cur.shape[1] >= 2 and cur.shape[0] % 2 == 0 and cur.shape[1] % 2 == 0:
        nxt = cv2.resize(cur, (cur.shape[1] // 2, cur.shape[0] // 2), interpolation=cv2.INTER_AREA)
        if nxt.ndim == 2:
            nxt = nxt[..., None]
        levels.append(np.ascontiguousarray(nxt, dtype=np.float32))
        cur = nxt
    shapes = np.array([src.shape[:2]] + [lv.shape[:2] for lv in levels], dtype=np.int64)
    sizes = [lv.size for lv in levels]
    offsets = np.concatenate([[0, 0], np.cumsum(sizes)[:-1]]).astype(np.int64)[:len(shapes)]
    rest = np.concatenate([lv.reshape(-1) for lv in levels]) if levels else np.zeros(1, np.float32)
    return Pyramid(src.reshape(-1), rest, shapes, offsets, src.shape[2], src)


def sample_footprint(pyr: Pyramid, band: FootprintBand, border: Border, out: np.ndarray,
                     alpha: np.ndarray) -> None:
    """Fill ``out`` and ``alpha`` for a footprint band (see the module docstring)."""
    wrap, top, bottom = border.flags
    _footprint(pyr.level0, pyr.rest, pyr.shapes, pyr.offsets, band.xs, band.ys, band.valid & ~band.edge,
               band.foot, wrap, top, bottom, MAX_TAPS, DENSITY, AXIS_TOL, out, alpha, work=16 * band.xs.size)
    if len(band.edge_idx):
        _edges(pyr.source, band.edge_idx, band.edge_xs, band.edge_ys, band.edge_valid, band.xs.shape[2],
               wrap, top, bottom, out, alpha)


@numba.njit(inline="always", cache=True)
def _bilinear_at(img, x, y, wrap, top, bottom, acc, weight):
    sh, sw, nc = img.shape
    fx0 = np.floor(x)
    fy0 = np.floor(y)
    i0 = int(fx0)
    j0 = int(fy0)
    tx = x - fx0
    ty = y - fy0
    for dj in range(2):
        wy = ty if dj else 1.0 - ty
        if wy == 0.0:
            continue
        for di in range(2):
            wx = tx if di else 1.0 - tx
            if wx == 0.0:
                continue
            ii, jj = fold_index(i0 + di, j0 + dj, sw, sh, wrap, top, bottom)
            ww = weight * wx * wy
            for ch in range(nc):
                acc[ch] += ww * img[jj, ii, ch]


@numba.njit(inline="always", cache=True)
def _tent_cdf(u):
    """Integral of the tent max(0, 1 - |t|) from -inf to u: 0.5 + v - v|v|/2 with v = clip(u, -1, 1)
    (the two quadratic pieces in one branch-free form)."""
    v = min(1.0, max(-1.0, u))
    return 0.5 + v - 0.5 * v * abs(v)


@numba.njit(inline="always", cache=True)
def _tent_box_weights(x, width, i0, n, k):
    """``k[:n]`` = weights of texels ``i0..i0+n-1`` when the bilinear reconstruction is averaged over
    the box of ``width`` centred at ``x`` (the tent integrated over the box); returns their sum."""
    s = 0.0
    if width < 1e-6:
        for i in range(n):
            k[i] = max(0.0, 1.0 - abs(x - (i0 + i)))
            s += k[i]
        return s
    hw = 0.5 * width
    inv = 1.0 / width
    for i in range(n):
        d = x - (i0 + i)
        k[i] = (_tent_cdf(d + hw) - _tent_cdf(d - hw)) * inv
        s += k[i]
    return s


@kernel.options(fastmath=True)
def _footprint(level0, rest, shapes, offsets, xs, ys, valid, foot, wrap, top, bottom, max_taps, density,
               axis_tol, out, alpha):
    h, w, n = xs.shape
    nc = out.shape[2]
    nlev = shapes.shape[0]
    inv = 1.0 / n
    h0 = shapes[0, 0]
    for r in range(h):
        acc = np.zeros(nc)
        kx = np.zeros(WINDOW)
        ky = np.zeros(WINDOW)
        wgt = np.zeros((WINDOW, WINDOW))
        for c in range(w):
            acc[:] = 0.0
            a0 = 0.0
            a1 = 0.0
            a2 = 0.0
            hits = 0
            for k in range(n):
                if not valid[r, c, k]:
                    continue
                hits += 1
                ax = np.float64(foot[r, c, k, 0])
                ay = np.float64(foot[r, c, k, 1])
                bx = np.float64(foot[r, c, k, 2])
                by = np.float64(foot[r, c, k, 3])
                la = np.sqrt(ax * ax + ay * ay)
                lb = np.sqrt(bx * bx + by * by)
                longest = max(la, lb)
                lev = 0
                while lev + 1 < nlev and longest > max_taps * (1 << lev):
                    lev += 1
                lh = shapes[lev, 0]
                lw = shapes[lev, 1]
                scale = lh / h0  # texels of this level per source pixel
                # second moments of the footprint (a parallelogram), in texels^2 x 12: the variance
                # of a box of width w is w^2 / 12
                sxx = (ax * ax + bx * bx) * scale * scale
                syy = (ay * ay + by * by) * scale * scale
                sxy = (ax * ay + bx * by) * scale * scale
                cx = (np.float64(xs[r, c, k]) + 0.5) * scale - 0.5
                cy = (np.float64(ys[r, c, k]) + 0.5) * scale - 0.5
                if sxx <= 9.0 and syy <= 9.0 and abs(sxy) <= axis_tol:
                    na = nb = nsl = 1  # x-y covariance about 0: one box has the footprint's second moments
                    bw = np.sqrt(sxx)
                    bh = np.sqrt(syy)
                else:
                    # na x nb cells along the footprint's sides, each averaged over the axis-aligned
                    # box with its second moments
                    na = max(1, int(np.ceil(la * scale * density)))
                    nb = max(1, int(np.ceil(lb * scale * density)))
                    nsl = na * nb
                    bw = scale * np.sqrt((ax / na) ** 2 + (bx / nb) ** 2)
                    bh = scale * np.sqrt((ay / na) ** 2 + (by / nb) ** 2)
                bw = min(3.0, bw)
                bh = min(3.0, bh)
                buf = level0 if lev == 0 else rest
                base = offsets[lev]
                if nsl == 1:  # one box: separable weights, read directly
                    i0 = int(np.floor(cx - 1.0 - 0.5 * bw)) + 1
                    j0 = int(np.floor(cy - 1.0 - 0.5 * bh)) + 1
                    ni = int(np.floor(cx + 1.0 + 0.5 * bw)) + 1 - i0
                    nj = int(np.floor(cy + 1.0 + 0.5 * bh)) + 1 - j0
                    norm = 1.0 / (_tent_box_weights(cx, bw, i0, ni, kx) * _tent_box_weights(cy, bh, j0, nj, ky))
                    inside = i0 >= 0 and j0 >= 0 and i0 + ni <= lw and j0 + nj <= lh
                    for j in range(nj):
                        wj = ky[j] * norm
                        for i in range(ni):
                            ww = kx[i] * wj
                            if inside:
                                p = base + ((j0 + j) * lw + i0 + i) * nc
                            else:
                                ii, jj = fold_index(i0 + i, j0 + j, lw, lh, wrap, top, bottom)
                                p = base + (jj * lw + ii) * nc
                            if nc == 3:
                                a0 += ww * buf[p]
                                a1 += ww * buf[p + 1]
                                a2 += ww * buf[p + 2]
                            else:
                                for ch in range(nc):
                                    acc[ch] += ww * buf[p + ch]
                    continue
                ex = 0.5 * scale * (abs(ax) * (1.0 - 1.0 / na) + abs(bx) * (1.0 - 1.0 / nb)) + 1.0 + 0.5 * bw
                ey = 0.5 * scale * (abs(ay) * (1.0 - 1.0 / na) + abs(by) * (1.0 - 1.0 / nb)) + 1.0 + 0.5 * bh
                wx0 = int(np.floor(cx - ex)) + 1
                wy0 = int(np.floor(cy - ey)) + 1
                nwx = min(int(np.floor(cx + ex)) - wx0 + 1, WINDOW)
                nwy = min(int(np.floor(cy + ey)) - wy0 + 1, WINDOW)
                for j in range(nwy):
                    for i in range(nwx):
                        wgt[j, i] = 0.0
                cell = 1.0 / nsl
                for q in range(nsl):
                    fa = (q % na + 0.5) / na - 0.5
                    fb = (q // na + 0.5) / nb - 0.5
                    px = cx + (fa * ax + fb * bx) * scale
                    py = cy + (fa * ay + fb * by) * scale
                    rx = 1.0 + 0.5 * bw
                    ry = 1.0 + 0.5 * bh
                    i0 = max(int(np.floor(px - rx)) + 1, wx0)
                    j0 = max(int(np.floor(py - ry)) + 1, wy0)
                    ni = min(int(np.floor(px + rx)) + 1, wx0 + nwx) - i0
                    nj = min(int(np.floor(py + ry)) + 1, wy0 + nwy) - j0
                    if ni <= 0 or nj <= 0:
                        continue
                    sx = _tent_box_weights(px, bw, i0, ni, kx)
                    sy = _tent_box_weights(py, bh, j0, nj, ky)
                    norm = cell / (sx * sy)
                    for j in range(nj):
                        wj = ky[j] * norm
                        for i in range(ni):
                            wgt[j0 - wy0 + j, i0 - wx0 + i] += kx[i] * wj
                inside = wx0 >= 0 and wy0 >= 0 and wx0 + nwx <= lw and wy0 + nwy <= lh
                for j in range(nwy):
                    for i in range(nwx):
                        ww = wgt[j, i]
                        if ww == 0.0:
                            continue
                        if inside:
                            p = base + ((wy0 + j) * lw + wx0 + i) * nc
                        else:
                            ii, jj = fold_index(wx0 + i, wy0 + j, lw, lh, wrap, top, bottom)
                            p = base + (jj * lw + ii) * nc
                        if nc == 3:
                            a0 += ww * buf[p]
                            a1 += ww * buf[p + 1]
                            a2 += ww * buf[p + 2]
                        else:
                            for ch in range(nc):
                                acc[ch] += ww * buf[p + ch]
            if nc == 3:
                acc[0] = a0
                acc[1] = a1
                acc[2] = a2
            for ch in range(nc):
                out[r, c, ch] = acc[ch] * inv
            alpha[r, c] = hits * inv


@numba.njit(cache=True, nogil=True)
def _edges(src, idx, exs, eys, evalid, n, wrap, top, bottom, out, alpha):
    """Add the split edge samples: each contributes (sum of its valid sub-samples) / (K n)."""
    nc = out.shape[2]
    w = out.shape[1]
    m, kk = exs.shape
    acc = np.zeros(nc)
    for e in range(m):
        pix = idx[e] // n
        r = pix // w
        c = pix % w
        acc[:] = 0.0
        hits = 0
        for q in range(kk):
            if evalid[e, q]:
                hits += 1
                _bilinear_at(src, np.float64(exs[e, q]), np.float64(eys[e, q]), wrap, top, bottom, acc, 1.0)
        scale = 1.0 / (kk * n)
        for ch in range(nc):
            out[r, c, ch] += acc[ch] * scale
        alpha[r, c] += hits * scale
