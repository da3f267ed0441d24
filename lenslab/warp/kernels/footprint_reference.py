"""NumPy reference of the compiled footprint filter (``src/native/footprint_runs.cpp``, :mod:`lenslab.warp.pyramid`),
for the tests: every step in float64 Python arithmetic, one readable step at a time, each footprint read through its own
window (the kernel shares windows between the footprints of a run of pixels: the same integral, float64 rounding
apart; ``src/native/footprint_chunks.h``). Slow: tests only.
"""

from __future__ import annotations

import math

import numpy as np

from lenslab.warp.kernels.positions import clamp_pos
from lenslab.warp.pyramid import MAX_TAPS, THIN, WINDOW, Pyramid
from lenslab.warp.seam import fold_taps as fold_index


def _tent_c(u: float) -> float:
    """The tent's antiderivative: 0 below -1, 1 above 1."""
    v = min(1.0, max(-1.0, u))
    return 0.5 + v - 0.5 * v * abs(v)


G2 = 0.5 / math.sqrt(3.0)  # the 2-point Gauss-Legendre nodes at mid -+ G2 * len


def slice_weights(cx, cy, ax, ay, bx, by, wx0, wy0, nwx, nwy):
    """``(weights (nwy, nwx) float64, area)``: texel (wx0 + i, wy0 + j)'s weight in the bilinear
    reconstruction integrated over the parallelogram ``c + s a + r b`` (s, r in [-1/2, 1/2]).

    Between consecutive breakpoints in y (the vertices and the texel rows) the slice's ends move
    linearly and each texel's weight is a cubic in y: 2-point Gauss-Legendre; across x each slice is
    integrated exactly by the tent's antiderivative, and split between the two texel rows around it by
    the linear interpolation of the bilinear reconstruction.
    """
    vx = [cx - 0.5 * ax - 0.5 * bx, cx + 0.5 * ax - 0.5 * bx, cx + 0.5 * ax + 0.5 * bx, cx - 0.5 * ax + 0.5 * bx]
    vy = [cy - 0.5 * ay - 0.5 * by, cy + 0.5 * ay - 0.5 * by, cy + 0.5 * ay + 0.5 * by, cy - 0.5 * ay + 0.5 * by]
    edges = []
    for e in range(4):
        f = (e + 1) % 4
        if vy[e] <= vy[f]:
            lo, xlo, hi, xhi = vy[e], vx[e], vy[f], vx[f]
        else:
            lo, xlo, hi, xhi = vy[f], vx[f], vy[e], vx[e]
        edges.append((lo, hi, xlo, (xhi - xlo) / (hi - lo) if hi > lo else 0.0))
    ys = sorted(vy)
    w = np.zeros((nwy + 2, nwx))  # rows -1 and nwy: scratch
    # only the window's rows -1 .. nwy - 1 (a footprint inside its window lies within them; a clipped one takes
    # its sum from the weights)
    y_end = min(ys[3], float(wy0 + nwy))
    total, y, v, seen, left, right = 0.0, max(ys[0], float(wy0 - 1)), 1, 0, edges[0], edges[0]
    while y < y_end:
        while v < 3 and ys[v] <= y:
            v += 1
        if v != seen:  # a new pair of vertices: the edges on the left and on the right until the next
            seen = v
            ym = 0.5 * (ys[v - 1] + ys[v])
            active = [(xlo + (ym - lo) * k, e) for e, (lo, hi, xlo, k) in enumerate(edges)
                      if lo <= ym <= hi and hi != lo]
            left = edges[min(active, key=lambda t: t[0])[1]] if active else edges[0]  # the first of equals
            right = edges[max(active, key=lambda t: t[0])[1]] if active else edges[0]
        y1 = min(ys[v], math.floor(y) + 1.0)
        length, mid = y1 - y, 0.5 * (y + y1)
        g = 0.5 * length
        pts = []
        for yy in (mid - G2 * length, mid + G2 * length):
            xl = left[2] + (yy - left[0]) * left[3]
            xr = max(xl, right[2] + (yy - right[0]) * right[3])
            total += g * (xr - xl)
            ty = yy - math.floor(mid)
            pts.append((xl, xr, g * (1.0 - ty), g * ty))
        j = math.floor(mid) - wy0
        if not -1 <= j < nwy:
            y = y1
            continue
        (xl0, xr0, a0, b0), (xl1, xr1, a1, b1) = pts
        lo_x, hi_x = min(xl0, xl1), max(xr0, xr1)
        for i in range(max(math.floor(lo_x - 1.0) + 1 - wx0, 0), min(math.floor(hi_x + 1.0) + 1 - wx0, nwx)):
            wa = _tent_c(xr0 - wx0 - i) - _tent_c(xl0 - wx0 - i)
            wb = _tent_c(xr1 - wx0 - i) - _tent_c(xl1 - wx0 - i)
            w[j + 1, i] += a0 * wa + a1 * wb
            w[j + 2, i] += b0 * wa + b1 * wb
        y = y1
    return w[1:-1], total


def window_rows(win: np.ndarray):
    """``(f, h, s)`` of a window's rows (``win`` (rows, texels, C) float64, the slices' rows first): the texels'
    values, half the step to the next texel, and the integral of the row's linear interpolant from texel 0 to
    each texel (trapezoids summed in order), so that the integral from texel 0 to ``u + t`` is ``s + t (f + t h)``."""
    f = np.asarray(win, dtype=np.float64)
    h = np.zeros_like(f)
    s = np.zeros_like(f)
    h[:, :-1] = 0.5 * (f[:, 1:] - f[:, :-1])
    for u in range(f.shape[1] - 2):
        s[:, u + 1] = s[:, u] + 0.5 * (f[:, u] + f[:, u + 1])
    return f, h, s


def edge_integral(xa, ya, xb, yb, sign, rows, acc):
    """``acc + sign *`` the integral over y of ``F(x(y), y)`` along the edge from ``(xa, ya)`` to ``(xb, yb)``
    (``ya <= yb``, window coordinates), ``F(x, y)`` the integral of the bilinear reconstruction along row y from
    the window's first texel to x. Cut at the texel rows, each piece by 2-point Gauss-Legendre."""
    if not yb > ya:
        return acc
    f, h, s = rows
    k = (xb - xa) / (yb - ya)
    umax, jmax = float(f.shape[1] - 2), f.shape[0] - 2
    n = math.floor(ya)
    while n < yb:
        y0, y1 = max(ya, n), min(yb, n + 1.0)
        length, mid = y1 - y0, 0.5 * (y0 + y1)
        g = sign * 0.5 * length
        j = min(jmax, max(0, int(n)))
        for yy in (mid - G2 * length, mid + G2 * length):
            x = xa + (yy - ya) * k
            uf = min(umax, max(0.0, math.floor(x)))
            t, ty, u = x - uf, yy - n, int(uf)
            f0 = s[j, u] + t * (f[j, u] + t * h[j, u])
            f1 = s[j + 1, u] + t * (f[j + 1, u] + t * h[j + 1, u])
            acc = acc + (g * (1.0 - ty)) * f0 + (g * ty) * f1
        n += 1.0
    return acc


def prefix_slices(cx, cy, ax, ay, bx, by, rows):
    """``(integral (C,), area)``: the bilinear reconstruction of a window's rows (:func:`window_rows`) integrated
    over the parallelogram ``c + s a + r b`` (s, r in [-1/2, 1/2]; window coordinates, texel (0, 0) the window's
    first). By Green's theorem: the integral over y of F at the right ends of its rows less F at the left ends,
    edge by edge (:func:`edge_integral`); the area is ``|a x b|``."""
    vx = [cx - 0.5 * ax - 0.5 * bx, cx + 0.5 * ax - 0.5 * bx, cx + 0.5 * ax + 0.5 * bx, cx - 0.5 * ax + 0.5 * bx]
    vy = [cy - 0.5 * ay - 0.5 * by, cy + 0.5 * ay - 0.5 * by, cy + 0.5 * ay + 0.5 * by, cy - 0.5 * ay + 0.5 * by]
    ib = 0
    for e in range(1, 4):  # the lowest vertex (the first of equals); the highest is opposite
        ib = e if vy[e] < vy[ib] else ib
    it, m1, m2 = (ib + 2) % 4, (ib + 1) % 4, (ib + 3) % 4
    cross = (vx[m1] - vx[ib]) * (vy[it] - vy[ib]) - (vy[m1] - vy[ib]) * (vx[it] - vx[ib])
    left, right = (m1, m2) if cross < 0.0 else (m2, m1)  # left of the line from the lowest to the highest
    acc = np.zeros(rows[0].shape[2])
    for a, b, sign in ((ib, right, 1.0), (right, it, 1.0), (ib, left, -1.0), (left, it, -1.0)):
        acc = edge_integral(vx[a], vy[a], vx[b], vy[b], sign, rows, acc)
    return acc, abs(ax * by - ay * bx)


def _sample(levels, h0, x, y, f):
    """A sample as the filter reads it: its level, centre and sides there (a line or a point given a thickness),
    its window and whether it is sliced along columns."""
    ax, ay, bx, by = (0.0 if math.isnan(t) else float(clamp_pos(t)) for t in f)  # NaN: a point
    longest = max(math.sqrt(ax * ax + ay * ay), math.sqrt(bx * bx + by * by))
    lev = 0
    while lev + 1 < len(levels) and longest > MAX_TAPS * (1 << lev):
        lev += 1
    scale = levels[lev].shape[0] / h0
    ax, ay, bx, by = ax * scale, ay * scale, bx * scale, by * scale
    cx = (float(clamp_pos(x)) + 0.5) * scale - 0.5
    cy = (float(clamp_pos(y)) + 0.5) * scale - 0.5
    thin = not abs(ax * by - ay * bx) >= THIN * THIN
    if thin:  # a line or a point: a thickness far below a texel
        la, lb = math.hypot(ax, ay), math.hypot(bx, by)
        if la >= lb and la > 0.0:
            bx, by = -THIN * ay / la, THIN * ax / la
        elif lb > 0.0:
            ax, ay = THIN * by / lb, -THIN * bx / lb
        else:
            ax, ay, bx, by = THIN, 0.0, 0.0, THIN
    # the window: every texel the thickened footprint touches
    ex, ey = 0.5 * (abs(ax) + abs(bx)) + 1.0, 0.5 * (abs(ay) + abs(by)) + 1.0
    wx0, wy0 = math.floor(cx - ex) + 1, math.floor(cy - ey) + 1
    nwx, nwy = math.floor(cx + ex) + 1 - wx0, math.floor(cy + ey) + 1 - wy0
    if nwx > WINDOW:  # a footprint beyond the coarsest level: the window centred on it
        wx0, nwx = math.floor(cx) + 1 - WINDOW // 2, WINDOW
    if nwy > WINDOW:
        wy0, nwy = math.floor(cy) + 1 - WINDOW // 2, WINDOW
    return dict(lev=lev, cx=cx, cy=cy, a=(ax, ay), b=(bx, by), thin=thin, win=[wx0, wy0, nwx, nwy], cols=ey > ex,
                quad=None)


def _within(gap, s):
    """Whether ``gap`` is within an eighth of the smaller height of the sample's parallelogram (its area over its
    longer side), squared: (8 gap)^2 |longer side|^2 <= area^2."""
    (ax, ay), (bx, by) = s["a"], s["b"]
    area, g8 = ax * by - ay * bx, 8.0 * gap
    return g8 * g8 * max(ax * ax + ay * ay, bx * bx + by * by) <= area * area


def _shareable(s):
    _, _, nwx, nwy = s["win"]
    return not s["cols"] and not s["thin"] and nwx <= WINDOW - 3 and nwy <= WINDOW - 3


def share_sides(row, widths, wrap):
    """Neighbouring pixels of an output row (``row``: each pixel's :func:`_sample`, None where not read) share the
    side between them: the right side (+a) of one and the left side (-a) of the next, both averaged, when both are
    parallelograms sliced along rows with room in their window, at one level, and those sides lie within an
    eighth of the smaller height of either (a neighbour across the seam of a wrapping source counted a turn
    nearer). Each pixel that shares a side gets ``quad``: its vertices V0 (-a -b) V1 (+a -b) V2 (+a +b)
    V3 (-a +b) from its centre, and the window of that quadrilateral."""
    def own(s, k):
        (ax, ay), (bx, by) = s["a"], s["b"]
        sa, sb = (-0.5, 0.5, 0.5, -0.5)[k], (-0.5, -0.5, 0.5, 0.5)[k]
        return [sa * ax + sb * bx, sa * ay + sb * by]
    for s in row:
        if s is not None:
            s["quad"] = [own(s, k) for k in range(4)]
            s["shared"] = [False, False]
    for left, right in zip(row[:-1], row[1:]):
        if left is None or right is None or not (_shareable(left) and _shareable(right)):
            continue
        if left["lev"] != right["lev"]:
            continue
        dx, dy = right["cx"] - left["cx"], right["cy"] - left["cy"]
        if wrap:
            period = float(widths[left["lev"]])
            dx -= period * round(dx / period)
        l1, l2 = own(left, 1), own(left, 2)
        r0, r3 = own(right, 0), own(right, 3)
        r0, r3 = [dx + r0[0], dy + r0[1]], [dx + r3[0], dy + r3[1]]
        gap = max(abs(l1[0] - r0[0]), abs(l1[1] - r0[1]), abs(l2[0] - r3[0]), abs(l2[1] - r3[1]))
        if not (_within(gap, left) and _within(gap, right)):
            continue
        p1 = [0.5 * (l1[0] + r0[0]), 0.5 * (l1[1] + r0[1])]
        p2 = [0.5 * (l2[0] + r3[0]), 0.5 * (l2[1] + r3[1])]
        left["quad"][1], left["quad"][2] = p1, p2
        right["quad"][0], right["quad"][3] = [p1[0] - dx, p1[1] - dy], [p2[0] - dx, p2[1] - dy]
        left["shared"][1] = right["shared"][0] = True
    for s in row:
        if s is None:
            continue
        if not any(s["shared"]):
            s["quad"] = None
            continue
        xs = [s["cx"] + v[0] for v in s["quad"]]
        ys = [s["cy"] + v[1] for v in s["quad"]]
        wx0, wy0 = math.floor(min(xs)), math.floor(min(ys))  # floor(x) and floor(x) + 1 for every x it spans
        s["win"] = [wx0, wy0, math.floor(max(xs)) + 2 - wx0, math.floor(max(ys)) + 2 - wy0]


def quad_integral(vx, vy, rows):
    """``(integral (C,), area)``: the bilinear reconstruction of a window's rows integrated over the quadrilateral
    V0 V1 V2 V3 (window coordinates), by Green's theorem around it (each directed edge upwards, negated when it
    runs down); the area is the signed shoelace area, of the contour's sign."""
    acc = np.zeros(rows[0].shape[2])
    for k in range(4):
        px, py, qx, qy = vx[k], vy[k], vx[(k + 1) % 4], vy[(k + 1) % 4]
        acc = edge_integral(px, py, qx, qy, 1.0, rows, acc) if qy > py else edge_integral(qx, qy, px, py, -1.0, rows, acc)
    area = 0.5 * sum(vx[k] * vy[(k + 1) % 4] - vx[(k + 1) % 4] * vy[k] for k in range(4))
    return acc, area


def _within_texels(mean, texels):
    """A footprint's mean kept within the least and greatest of the texels its window read (each channel), where
    they are all finite: the exact box average of a bilinear reconstruction is a convex combination of them, so
    this removes only float64 rounding (the kernel keeps it within its run's shared window, a looser bound of the
    same kind). NaN stays NaN."""
    if not np.isfinite(texels).all():
        return mean
    lo, hi = texels.min(axis=0), texels.max(axis=0)
    return np.where(mean < lo, lo, np.where(mean > hi, hi, mean))


def footprint(pyr: Pyramid, xs, ys, valid, foot, border):
    """The footprint filter (see :mod:`lenslab.warp.antialias`): ``(out (n, C), alpha (n,))`` for pixels of
    ``S`` samples (``xs`` (..., S), ``foot`` (..., S, 4)), every step in float64 Python arithmetic. Rows of
    pixels of one sample (``xs`` (rows, width, 1)) share the sides between neighbours (:func:`share_sides`)."""
    ns = xs.shape[-1]
    width = xs.shape[1] if np.ndim(xs) == 3 and ns == 1 else 1
    x, y, v = (np.asarray(a).reshape(-1, ns) for a in (xs, ys, valid))
    f = np.asarray(foot, dtype=np.float64).reshape(-1, ns, 4)
    nc = pyr.channels
    levels = [pyr.source] + [pyr.rest[o:o + h * w * nc].reshape(h, w, nc)
                             for o, (h, w) in zip(pyr.offsets[1:], pyr.shapes[1:])]
    h0 = float(pyr.shapes[0, 0])
    samples = [[_sample(levels, h0, x[q, s], y[q, s], f[q, s]) if v[q, s] else None for s in range(ns)]
               for q in range(x.shape[0])]
    if width > 1:
        for r0 in range(0, x.shape[0], width):
            share_sides([samples[q][0] for q in range(r0, r0 + width)], pyr.shapes[:, 1], border[0])
    out = np.zeros((x.shape[0], nc))
    alpha = np.zeros(x.shape[0])
    for q in range(x.shape[0]):
        acc = np.zeros(nc)
        hits = 0
        for smp in samples[q]:
            if smp is None:
                continue
            hits += 1
            img = levels[smp["lev"]]
            lh, lw = img.shape[:2]
            cx, cy, (ax, ay), (bx, by) = smp["cx"], smp["cy"], smp["a"], smp["b"]
            wx0, wy0, nwx, nwy = smp["win"]
            ex, ey = 0.5 * (abs(ax) + abs(bx)) + 1.0, 0.5 * (abs(ay) + abs(by)) + 1.0
            jj, ii = np.mgrid[wy0:wy0 + nwy, wx0:wx0 + nwx]
            fi, fj = fold_index(ii.ravel(), jj.ravel(), lw, lh, *border)
            texels = img[fj, fi].astype(np.float64)
            if smp.get("quad") is not None:  # a quadrilateral sharing a side
                part, area = quad_integral([cx - wx0 + p[0] for p in smp["quad"]],
                                           [cy - wy0 + p[1] for p in smp["quad"]],
                                           window_rows(texels.reshape(nwy, nwx, nc)))
                acc += _within_texels(part * (1.0 / area), texels)
                continue
            if nwx < WINDOW and nwy < WINDOW:  # inside its window: the rows' prefix sums
                win = texels.reshape(nwy, nwx, nc)
                if ey > ex:  # sliced along the shorter extent: here x, so x and y swap roles
                    part, area = prefix_slices(cy - wy0, cx - wx0, ay, ax, by, bx, window_rows(win.transpose(1, 0, 2)))
                else:
                    part, area = prefix_slices(cx - wx0, cy - wy0, ax, ay, bx, by, window_rows(win))
                acc += _within_texels(part * (1.0 / area), texels)
                continue
            # clipped by its window (beyond the coarsest level): the texels' weights
            if ey > ex:
                wt, area = slice_weights(cy, cx, ay, ax, by, bx, wy0, wx0, nwy, nwx)
                wt = wt.T
            else:
                wt, area = slice_weights(cx, cy, ax, ay, bx, by, wx0, wy0, nwx, nwy)
            area = float(wt.sum())
            acc += (wt.ravel()[:, None] * texels).sum(axis=0) * (1.0 / area)
        out[q] = acc / ns
        alpha[q] = hits / ns
    return out.astype(np.float32), alpha.astype(np.float32)
