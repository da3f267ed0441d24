"""NumPy references of the compiled separable samplers and piece folding (:mod:`lenslab.warp.filters`,
:func:`lenslab.warp.seam.fold_piece`; ``src/native/separable.cpp``), for the tests.

Vectorised over pixels, every float64 step in the kernel's order (the kernel is built without fused
multiply-adds), so every filter gives the kernel's bits (Lanczos' sine and cosine are the same polynomial in both).
"""

from __future__ import annotations

import numpy as np

from lenslab.warp.seam import fold_taps


def weight(kind: int, t: np.ndarray) -> np.ndarray:
    """The tent (kind 1) or Catmull-Rom (kind 2) weight at offsets ``t`` (float64)."""
    a = np.abs(t)
    if kind == 1:
        return np.maximum(0.0, 1.0 - a)
    return np.where(a < 1.0, (1.5 * a - 2.5) * a * a + 1.0,
                    np.where(a < 2.0, ((-0.5 * a + 2.5) * a - 4.0) * a + 2.0, 0.0))


SIN_C = [1.0, -1.0 / 6.0, 1.0 / 120.0, -1.0 / 5040.0, 1.0 / 362880.0, -1.0 / 39916800.0, 1.0 / 6227020800.0,
         -1.0 / 1307674368000.0]  # (-1)^i / (2 i + 1)!
COS_C = [1.0, -0.5, 1.0 / 24.0, -1.0 / 720.0, 1.0 / 40320.0, -1.0 / 3628800.0, 1.0 / 479001600.0,
         -1.0 / 87178291200.0, 1.0 / 20922789888000.0]  # (-1)^i / (2 i)!


def small_sincos(z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``sin z, cos z`` for ``|z| <= pi / 6`` (float64): Taylor series to ``z^15`` and ``z^16`` by Horner's rule."""
    z2 = z * z
    ps, pc = np.full_like(z, SIN_C[7]), np.full_like(z, COS_C[8])
    for i in range(6, -1, -1):
        ps = ps * z2 + SIN_C[i]
    for i in range(7, -1, -1):
        pc = pc * z2 + COS_C[i]
    return z * ps, pc


def lanczos_weights(x: np.ndarray) -> list[np.ndarray]:
    """The Lanczos-3 weights of taps ``floor(x) - 2 .. floor(x) + 3`` at positions ``x`` (float64), unnormalised,
    from one sine and cosine of ``pi g / 3``, ``g = x - round(x)``: the tap at ``d = g + k`` has ``sin(pi d) =
    (-1)^k s (3 - 4 s^2)`` and ``sin(pi d / 3) = s cos(k pi / 3) + c sin(k pi / 3)``; the window times ``prod_s
    (pi d_s)^2 / 3`` (the normalisation takes it out): no division. The tap's own weight where ``|g| < 1e-60``."""
    i0, n = np.floor(x), np.floor(x + 0.5)
    g = x - n
    s, c = small_sincos(np.pi * g / 3.0)
    sp = s * (3.0 - 4.0 * s * s)
    half = 0.8660254037844386
    cos_k = np.array([-1.0, -0.5, 0.5, 1.0, 0.5, -0.5, -1.0])  # k = -3..3
    sin_k = np.array([0.0, -half, -half, 0.0, half, half, 0.0])
    den = [(np.pi * (x - (i0 - 2.0 + float(t)))) ** 2 for t in range(6)]
    pre, suf = [np.ones_like(x)] * 6, [np.ones_like(x)] * 6
    for t in range(1, 6):
        pre[t] = pre[t - 1] * den[t - 1]
    for t in range(4, -1, -1):
        suf[t] = suf[t + 1] * den[t + 1]
    own = np.abs(g) < 1e-60
    out = []
    for t in range(6):
        r = (n - i0).astype(np.int64) + 5 - t  # k + 3
        sd = np.where((r & 1) == 1, sp, -sp)
        v = sd * (s * cos_k[r] + c * sin_k[r]) * (pre[t] * suf[t])
        out.append(np.where(own, np.where(r == 3, 1.0, 0.0), v))
    return out


def axis_weights(kind: int, x: np.ndarray) -> list[np.ndarray]:
    """The ``2 kind`` weights of one axis at positions ``x`` (taps from ``floor(x) - kind + 1``), each times the
    reciprocal of their sum (the sum taken in tap order)."""
    i0 = np.floor(x)
    w = lanczos_weights(x) if kind == 3 else [weight(kind, x - (i0 - float(kind - 1 - t))) for t in range(2 * kind)]
    total = 0.0
    for t in range(2 * kind):
        total = total + w[t]
    inv = 1.0 / total
    return [wt * inv for wt in w]


def piece_at(x, y, grid: np.ndarray, cell: tuple[int, int]) -> np.ndarray:
    """The piece under index coordinates ``(x, y)`` (pixel centres at whole numbers), -1 outside the grid."""
    col = np.floor((x + 0.5) / cell[0])
    row = np.floor((y + 0.5) / cell[1])
    inside = (col >= 0) & (row >= 0) & (col < grid.shape[1]) & (row < grid.shape[0])
    return np.where(inside, grid[np.where(inside, row, 0).astype(np.int64), np.where(inside, col, 0).astype(np.int64)],
                    -1)


def fold_piece(i, j, p, table: np.ndarray):
    """Taps ``(i, j)`` of samples in pieces ``p`` (integer arrays) folded into their piece or across the edge
    they leave (the deeper of two for a corner) into the neighbour; clamped where nothing lies across."""
    i, j, p = (np.asarray(a, dtype=np.int64) for a in (i, j, p))
    x0, y0, pw, ph = (table[p, c] for c in range(4))
    li, lj = i - x0, j - y0
    inside = (li >= 0) & (lj >= 0) & (li < pw) & (lj < ph)
    ex = np.where(li < 0, -1 - li, li - pw)
    ey = np.where(lj < 0, -1 - lj, lj - ph)
    across_x = ex >= ey
    edge = np.where(across_x, np.where(li < 0, 0, 1), np.where(lj < 0, 2, 3))
    k = np.where(across_x, ex, ey)
    s = np.where(across_x, np.clip(lj, 0, ph - 1), np.clip(li, 0, pw - 1))
    q = table[p, 4 + 3 * edge]
    e2 = np.where(q >= 0, table[p, 5 + 3 * edge], 0)
    qq = np.maximum(q, 0)
    qx, qy, qw, qh = (table[qq, c] for c in range(4))
    s = np.where(table[p, 6 + 3 * edge] != 0, np.where(edge < 2, ph, pw) - 1 - s, s)
    s = np.clip(s, 0, np.where(e2 < 2, qh, qw) - 1)
    k = np.minimum(k, np.where(e2 < 2, qw, qh) - 1)
    fi = np.select([e2 == 0, e2 == 1], [qx + k, qx + qw - 1 - k], qx + s)
    fj = np.select([e2 < 2, e2 == 2], [qy + s, qy + k], qy + qh - 1 - k)
    fi = np.where(q < 0, np.clip(i, x0, x0 + pw - 1), fi)
    fj = np.where(q < 0, np.clip(j, y0, y0 + ph - 1), fj)
    return np.where(inside, i, fi), np.where(inside, j, fj)


def separable(src: np.ndarray, xs, ys, valid, border, kind: int):
    """The separable sampler: ``(out (n, C) float32, alpha (n,) float32)`` for pixels of ``S`` samples
    (``xs`` (..., S)); ``border`` a :class:`~lenslab.warp.seam.Border` (its pieces fold the taps)."""
    ns = xs.shape[-1]
    x = np.asarray(xs, np.float32).reshape(-1, ns).astype(np.float64)
    y = np.asarray(ys, np.float32).reshape(-1, ns).astype(np.float64)
    v = np.asarray(valid, bool).reshape(-1, ns)
    sh, sw, nc = src.shape
    rad = max(kind, 1)
    acc = np.zeros((x.shape[0], nc))
    for k in range(ns):
        xk, yk, vk = x[:, k], y[:, k], v[:, k]
        piece = piece_at(xk, yk, border.grid, border.cell) if border.has_pieces else np.full(len(xk), -1)

        def read(ii, jj):
            fi, fj = fold_taps(ii, jj, sw, sh, *border.flags)
            if border.has_pieces:
                pi, pj = fold_piece(ii, jj, np.maximum(piece, 0), border.pieces)
                fi, fj = np.where(piece >= 0, pi, fi), np.where(piece >= 0, pj, fj)
            return src[fj, fi].astype(np.float64)

        if kind == 0:
            acc = acc + np.where(vk[:, None], read(np.floor(xk + 0.5), np.floor(yk + 0.5)), 0.0)
            continue
        i0, j0 = np.floor(xk), np.floor(yk)
        wx, wy = axis_weights(kind, xk), axis_weights(kind, yk)
        val = np.zeros_like(acc)
        for tj in range(2 * rad):  # each row's taps weighted by wx, then the rows by wy; taps of weight 0 not read
            row = np.zeros_like(acc)
            for ti in range(2 * rad):
                term = wx[ti][:, None] * read(i0 - rad + 1 + ti, j0 - rad + 1 + tj)
                row = row + np.where((wx[ti] != 0.0)[:, None], term, 0.0)
            val = val + np.where((wy[tj] != 0.0)[:, None], wy[tj][:, None] * row, 0.0)
        acc = acc + np.where(vk[:, None], val, 0.0)
    big = float(np.finfo(np.float32).max)
    mean = acc * (1.0 / ns)
    return np.clip(mean, -big, big).astype(np.float32), (v.sum(axis=1) * (1.0 / ns)).astype(np.float32)
