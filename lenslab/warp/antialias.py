"""Anti-aliasing by footprint: average the source over the region each output pixel covers.

Where the output shrinks the source (a wide fisheye from a detailed panorama, the rows near a pole),
one bilinear tap per pixel skips most of the source and small bright features (the sun) flicker in
and out. Supersampling (``samples=N``) fixes it at N times the cost everywhere. The footprint
prefilter spends the work only where it is needed:

1. The local Jacobian of the map gives the pixel's footprint on the source: the parallelogram
   spanned by ``a = q(p + (1/2, 0)) - q(p - (1/2, 0))`` and ``b = q(p + (0, 1/2)) - q(p - (0, 1/2))``
   (secants across the pixel, in source pixels, the seam unwrapped), per sub-sample when combined
   with ``samples``.
2. A box-filtered pyramid of the source (each level halves the previous by 2x2 averaging; the seam
   and pole structure of an equirect survives the halving) provides pre-averaged texels.
3. The level ``L`` is the finest at which the footprint spans at most ``MAX_TAPS`` texels along its
   longer side; the parallelogram is then split into ``na x nb`` cells, about ``1/DENSITY`` texel
   each along ``a`` and ``b`` (anisotropic: a long thin footprint near a pole gets many cells along
   its length, few across), or kept whole when its edges lie within ``AXIS_TOL`` texel of the axes.
4. Each cell is replaced by the axis-aligned box with the same second moments, and the bilinear
   reconstruction is averaged over that box exactly: separable weights, the tent integrated over the
   box (:func:`_box_tent`). The cells' means are averaged.

The result approximates the box average of the bilinear reconstruction over the pixel, which is what
dense supersampling converges to; ``lenslab bench warp`` measures the difference on real panoramas.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numba
import numpy as np
from numba import prange

from lenslab.warp.dispatch import kernel
from lenslab.warp.maps import MapBand, Mapper, exact_map
from lenslab.warp.seam import Border, fold_index

JACOBIAN_POINTS = 5  # map evaluations per sample: the centre and the four secant ends
EDGE_SPLIT = 4  # a sample whose footprint straddles the edge of the valid region becomes EDGE_SPLIT^2 samples
MAX_TAPS = 8.0  # longest side of a footprint, in texels of the level it is read from
AXIS_TOL = 0.25  # texels: a footprint whose edges stray less than this from the axes is one box
DENSITY = 0.75  # cells per texel along each side of the footprint (measured best accuracy per cost)


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
    # centre, then -x, +x, -y, +y; the lattice/exact map handles each shifted set like any samples
    shifts = np.array([[0, 0], [-half, 0], [half, 0], [0, -half], [0, half]], dtype=np.float64)
    allo = (offsets[..., None, :, :] + shifts[:, None, :]).reshape(offsets.shape[:2] + (5 * n, 2))
    band = mapper.map_band(r0, r1, allo)
    h, w = r1 - r0, mapper.width
    xs = band.xs.reshape(h, w, 5, n)
    ys = band.ys.reshape(h, w, 5, n)
    vs = band.valid.reshape(h, w, 5, n)
    foot = np.empty((h, w, n, 4), dtype=np.float32)
    _secants(xs, ys, vs, mapper.wrap, foot, work=xs.size)
    # samples whose five points disagree on validity straddle the edge of the valid region (a
    # fisheye's rim, a source image's border): their coverage is partial, so they are split into
    # EDGE_SPLIT x EDGE_SPLIT plain sub-samples that measure it
    edge = vs.any(axis=2) & ~vs.all(axis=2)
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
    return FootprintBand(r0, r1, np.ascontiguousarray(xs[:, :, 0]), np.ascontiguousarray(ys[:, :, 0]),
                         np.ascontiguousarray(vs[:, :, 0]), foot, edge, flat,
                         (exy[..., 0] - 0.5).astype(np.float32), (exy[..., 1] - 0.5).astype(np.float32), ev)


@kernel
def _secants(xs, ys, vs, wrap, foot):
    h, w, _, n = xs.shape
    for r in prange(h):
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
               band.foot, wrap, top, bottom, MAX_TAPS, DENSITY, out, alpha, work=16 * band.xs.size)
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
def _box_tent(d, width):
    """Mean of the tent over [d - width/2, d + width/2]: the weight of a texel at distance d when the
    bilinear reconstruction is averaged over a box of that width (a tent itself when width -> 0)."""
    if width < 1e-6:
        return max(0.0, 1.0 - abs(d))
    return (_tent_cdf(d + 0.5 * width) - _tent_cdf(d - 0.5 * width)) / width


@numba.njit(inline="always", cache=True)
def _box_at(buf, base, sh, sw, nc, x, y, bw, bh, wrap, top, bottom, acc, weight, kx, ky):
    """Add ``weight`` x the mean of a level's bilinear reconstruction over the box (bw x bh) centred at
    (x, y); the level is ``buf[base:]``, ``sh x sw x nc``."""
    rx = 1.0 + 0.5 * bw
    ry = 1.0 + 0.5 * bh
    i0 = int(np.floor(x - rx)) + 1
    j0 = int(np.floor(y - ry)) + 1
    ni = min(int(np.floor(x + rx)) - i0 + 1, kx.shape[0])
    nj = min(int(np.floor(y + ry)) - j0 + 1, ky.shape[0])
    sx = 0.0
    for i in range(ni):
        kx[i] = _box_tent(x - (i0 + i), bw)
        sx += kx[i]
    sy = 0.0
    for j in range(nj):
        ky[j] = _box_tent(y - (j0 + j), bh)
        sy += ky[j]
    norm = weight / (sx * sy)
    inside = i0 >= 0 and j0 >= 0 and i0 + ni <= sw and j0 + nj <= sh
    for j in range(nj):
        wj = ky[j] * norm
        if wj == 0.0:
            continue
        for i in range(ni):
            ww = kx[i] * wj
            if ww == 0.0:
                continue
            if inside:
                p = base + ((j0 + j) * sw + i0 + i) * nc
            else:
                ii, jj = fold_index(i0 + i, j0 + j, sw, sh, wrap, top, bottom)
                p = base + (jj * sw + ii) * nc
            for ch in range(nc):
                acc[ch] += ww * buf[p + ch]


@kernel.options(fastmath=True)
def _footprint(level0, rest, shapes, offsets, xs, ys, valid, foot, wrap, top, bottom, max_taps, density,
               out, alpha):
    h, w, n = xs.shape
    nc = out.shape[2]
    nlev = shapes.shape[0]
    inv = 1.0 / n
    h0 = shapes[0, 0]
    for r in prange(h):
        acc = np.zeros(nc)
        kx = np.zeros(8)
        ky = np.zeros(8)
        for c in range(w):
            acc[:] = 0.0
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
                na = max(1, int(np.ceil(la * scale * density)))
                nb = max(1, int(np.ceil(lb * scale * density)))
                if (la * scale <= 3.0 and lb * scale <= 3.0 and min(abs(ax), abs(ay)) * scale <= AXIS_TOL
                        and min(abs(bx), abs(by)) * scale <= AXIS_TOL):
                    na = nb = 1  # edges within AXIS_TOL texel of the axes: one box covers it exactly enough
                # each of the na x nb cells of the footprint is averaged over the axis-aligned box
                # with the same second moments (exact for an axis-aligned footprint)
                bw = min(3.0, scale * np.sqrt((ax / na) ** 2 + (bx / nb) ** 2))
                bh = min(3.0, scale * np.sqrt((ay / na) ** 2 + (by / nb) ** 2))
                cx = np.float64(xs[r, c, k]) + 0.5
                cy = np.float64(ys[r, c, k]) + 0.5
                wgt = 1.0 / (na * nb)
                for j in range(nb):
                    fb = (j + 0.5) / nb - 0.5
                    for i in range(na):
                        fa = (i + 0.5) / na - 0.5
                        px = (cx + fa * ax + fb * bx) * scale - 0.5
                        py = (cy + fa * ay + fb * by) * scale - 0.5
                        if lev == 0:
                            _box_at(level0, 0, lh, lw, nc, px, py, bw, bh, wrap, top, bottom, acc, wgt, kx, ky)
                        else:
                            _box_at(rest, offsets[lev], lh, lw, nc, px, py, bw, bh, wrap, top, bottom, acc, wgt,
                                    kx, ky)
            for ch in range(nc):
                out[r, c, ch] = acc[ch] * inv
            alpha[r, c] = hits * inv


@numba.njit(cache=True)
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
