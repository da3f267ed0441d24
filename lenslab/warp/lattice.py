"""The map lattice's arithmetic: ghost nodes beyond the valid region, Catmull-Rom coefficients per cell,
and the compiled kernels that evaluate a band of the map from them (see :mod:`lenslab.warp.maps`)."""

from __future__ import annotations

import numba
import numpy as np

from lenslab.warp.kernels.dispatch import kernel


def ghost_nodes(nx, ny, valid, wrap):
    """Fill invalid lattice nodes next to valid ones by extrapolation (an x pass, then a y pass):
    quadratic from three valid neighbours in a line, linear from two (never from nodes within three
    of the lattice's far edge, as before: the first and last three nodes along the pass are skipped).

    Returns the filled x and y node values (C-contiguous float64) and which nodes now have a value.
    """
    gx = np.ascontiguousarray(nx, dtype=np.float64).copy()
    gy = np.ascontiguousarray(ny, dtype=np.float64).copy()
    have = np.ascontiguousarray(valid, dtype=np.bool_).copy()
    _ghost_pass(gx, gy, have, float(wrap))
    return gx, gy, have


@numba.njit(cache=True, nogil=True)
def _ghost_pass(gx, gy, have, wrap):
    rows, cols = gx.shape
    for axis in (1, 0):
        known = have.copy()
        n = cols if axis == 1 else rows
        for step in (1, -1):
            for a in range(rows):
                for b in range(cols):
                    if have[a, b]:
                        continue
                    k = b if axis == 1 else a
                    if (step == 1 and k < 3) or (step == -1 and k > n - 4):
                        continue
                    a1, b1 = (a, b - step) if axis == 1 else (a - step, b)
                    a2, b2 = (a, b - 2 * step) if axis == 1 else (a - 2 * step, b)
                    if not (known[a1, b1] and known[a2, b2]):
                        continue
                    a3, b3 = (a, b - 3 * step) if axis == 1 else (a - 3 * step, b)
                    x1, x2 = gx[a1, b1], gx[a2, b2]
                    y1, y2 = gy[a1, b1], gy[a2, b2]
                    if wrap > 0.0:  # unwrap the neighbours relative to the nearest
                        x2 = x2 - wrap * np.round((x2 - x1) / wrap)
                    if known[a3, b3]:
                        x3, y3 = gx[a3, b3], gy[a3, b3]
                        if wrap > 0.0:
                            x3 = x3 - wrap * np.round((x3 - x1) / wrap)
                        gx[a, b] = 3.0 * x1 - 3.0 * x2 + x3
                        gy[a, b] = 3.0 * y1 - 3.0 * y2 + y3
                    else:
                        gx[a, b] = 2.0 * x1 - x2
                        gy[a, b] = 2.0 * y1 - y2
                    have[a, b] = True


@numba.njit(inline="always", cache=True)
def _cr_weights(t):
    t2 = t * t
    t3 = t2 * t
    return (
        0.5 * (-t3 + 2.0 * t2 - t),
        0.5 * (3.0 * t3 - 5.0 * t2 + 2.0),
        0.5 * (-3.0 * t3 + 4.0 * t2 + t),
        0.5 * (t3 - t2),
    )


@numba.njit(inline="always", cache=True)
def _cr_eval(nx, ny, ca, cb, tx, ty, wrap):
    wx = _cr_weights(tx)
    wy = _cr_weights(ty)
    ref = nx[cb + 1, ca + 1]
    sx = 0.0
    sy = 0.0
    for j in range(4):
        rx = 0.0
        ry = 0.0
        for i in range(4):
            v = nx[cb + j, ca + i]
            if wrap > 0.0:
                v -= wrap * np.floor((v - ref) / wrap + 0.5)
            rx += wx[i] * v
            ry += wx[i] * ny[cb + j, ca + i]
        sx += wy[j] * rx
        sy += wy[j] * ry
    return sx, sy


@numba.njit(cache=True, nogil=True)
def lattice_grid(nx, ny, tx, ty, wrap):
    ncy = nx.shape[0] - 3
    ncx = nx.shape[1] - 3
    ox = np.empty((ncy, ncx))
    oy = np.empty((ncy, ncx))
    for cb in range(ncy):
        for ca in range(ncx):
            ox[cb, ca], oy[cb, ca] = _cr_eval(nx, ny, ca, cb, tx, ty, wrap)
    return ox, oy


#: Catmull-Rom basis: weight_i(t) = sum_a _CR[i, a] t^a
CR_BASIS = np.array([[0.0, -0.5, 1.0, -0.5], [1.0, 0.0, -2.5, 1.5], [0.0, 0.5, 2.0, -1.5], [0.0, 0.0, -0.5, 0.5]])


@numba.njit(cache=True, nogil=True)
def cell_coefficients(nodes, state, cb0, cb1, wrap, cr_basis, coef):
    """Fill ``coef[row, ca, q]`` = CR^T P CR (``c[b, a]`` of tx^a ty^b) for the cells that interpolate:
    x and y for state 1, the direction for state 2; the x stencil unwrapped across the seam."""
    ncx = state.shape[1]
    p = np.empty((4, 4))
    t = np.empty((4, 4))
    for cb in range(cb0, cb1):
        for ca in range(ncx):
            st = state[cb, ca]
            if st <= 0:
                continue
            q0, q1 = (0, 2) if st == 1 else (2, 5)
            for q in range(q0, q1):
                ref = nodes[q, cb + 1, ca + 1]
                for j in range(4):
                    for i in range(4):
                        v = nodes[q, cb + j, ca + i]
                        if q == 0 and wrap > 0.0:
                            v -= wrap * np.floor((v - ref) / wrap + 0.5)
                        p[j, i] = v
                # t = p @ CR, then c = CR^T @ t
                for j in range(4):
                    for a in range(4):
                        acc = 0.0
                        for i in range(4):
                            acc += p[j, i] * cr_basis[i, a]
                        t[j, a] = acc
                for b in range(4):
                    for a in range(4):
                        acc = 0.0
                        for j in range(4):
                            acc += cr_basis[j, b] * t[j, a]
                        coef[cb - cb0, ca, q, b, a] = acc


@numba.njit(inline="always", cache=True)
def _poly(coef, cr, ca, q, tx, ty):
    acc = 0.0
    for b in range(3, -1, -1):
        acc = acc * ty + (((coef[cr, ca, q, b, 3] * tx + coef[cr, ca, q, b, 2]) * tx
                           + coef[cr, ca, q, b, 1]) * tx + coef[cr, ca, q, b, 0])
    return acc


NEED_DONE, NEED_EXACT, NEED_PROJECT = 0, 1, 2  # what a sample still needs after the lattice kernels


@numba.njit(inline="always", cache=True)
def _store_cell(st, r, c, k, x, y, dx, dy, dz, xs, ys, valid, need, dirs):
    """One sample from its cell: a position (state 1), a direction to project (2), exact (0) or none (-1)."""
    if st == 1:
        xs[r, c, k] = x - 0.5
        ys[r, c, k] = y - 0.5
        valid[r, c, k] = True
        need[r, c, k] = NEED_DONE
        return
    xs[r, c, k] = 0.0
    ys[r, c, k] = 0.0
    valid[r, c, k] = False
    if st == 2:
        dirs[r, c, k, 0] = dx
        dirs[r, c, k, 1] = dy
        dirs[r, c, k, 2] = dz
        need[r, c, k] = NEED_PROJECT
    else:
        need[r, c, k] = NEED_EXACT if st == 0 else NEED_DONE


@kernel
def lattice_eval(coef, state, cb0, step, r0, offs, xs, ys, valid, need, dirs):
    """The map of a band from the lattice, per-sample offsets ``offs`` (h, W, S, 2): index coordinates,
    validity, and per sample what it still needs (``NEED_*``; ``dirs`` holds the directions to project)."""
    h, w, n = xs.shape
    ho, wo = offs.shape[0], offs.shape[1]
    ncy, ncx = state.shape
    inv = 1.0 / step
    for r in range(h):
        ro = r % ho
        for c in range(w):
            co = c if wo > 1 else 0
            for k in range(n):
                px = (c + offs[ro, co, k, 0]) * inv
                py = (r0 + r + offs[ro, co, k, 1]) * inv
                ca = min(max(int(np.floor(px)), 0), ncx - 1)
                cb = min(max(int(np.floor(py)), 0), ncy - 1)
                st = state[cb, ca]
                tx = px - ca
                ty = py - cb
                cr = cb - cb0
                x = y = dx = dy = dz = 0.0
                if st == 1:
                    x = _poly(coef, cr, ca, 0, tx, ty)
                    y = _poly(coef, cr, ca, 1, tx, ty)
                elif st == 2:
                    dx = _poly(coef, cr, ca, 2, tx, ty)
                    dy = _poly(coef, cr, ca, 3, tx, ty)
                    dz = _poly(coef, cr, ca, 4, tx, ty)
                _store_cell(st, r, c, k, x, y, dx, dy, dz, xs, ys, valid, need, dirs)


@numba.njit(inline="always", cache=True)
def row_cubics(coef, cr, ca, st, ty, rc):
    """``rc[q]``: the cubic in tx that cell ``ca``'s bicubic becomes along a row at ``ty`` (x, y for
    state 1, the direction for state 2)."""
    if st > 0:
        q0, q1 = (0, 2) if st == 1 else (2, 5)
        for q in range(q0, q1):
            for a in range(4):
                rc[q, a] = ((coef[cr, ca, q, 3, a] * ty + coef[cr, ca, q, 2, a]) * ty
                            + coef[cr, ca, q, 1, a]) * ty + coef[cr, ca, q, 0, a]


@numba.njit(inline="always", cache=True)
def cubic(rc, q, tx):
    return ((rc[q, 3] * tx + rc[q, 2]) * tx + rc[q, 1]) * tx + rc[q, 0]


@numba.njit(cache=True, nogil=True)
def lattice_rows(coef, state, cb0, inv, r0, offs, xs, ys, valid, need, dirs):
    """:func:`lattice_eval` for offsets shared by every pixel: along a row of samples ty is fixed, so
    each cell's bicubic collapses to a cubic in tx (``rc``), made once per cell and row. A row is walked
    cell by cell: the samples of an interpolating cell (state 1) are one loop of two cubics over
    contiguous rows of ``xs`` and ``ys``, with nothing else in it, which the compiler vectorises."""
    h, w, n = xs.shape
    ncy, ncx = state.shape
    rc = np.empty((5, 4))
    for r in range(h):
        for k in range(n):
            ox = offs[0, 0, k, 0]
            py = (r0 + r + offs[0, 0, k, 1]) * inv
            cb = min(max(int(np.floor(py)), 0), ncy - 1)
            ty = py - cb
            cr = cb - cb0
            xr = xs[r, :, k]
            yr = ys[r, :, k]
            vr = valid[r, :, k]
            nr = need[r, :, k]
            c = 0
            while c < w:
                ca = min(max(int(np.floor((c + ox) * inv)), 0), ncx - 1)
                c1 = w  # the samples up to c1 share cell ca: floor((c + ox) inv) < ca + 1 (the last cell: all)
                if ca < ncx - 1:
                    c1 = min(w, max(c + 1, int(np.ceil((ca + 1) / inv - ox))))
                    while c1 > c + 1 and (c1 - 1 + ox) * inv >= ca + 1:
                        c1 -= 1
                    while c1 < w and (c1 + ox) * inv < ca + 1:
                        c1 += 1
                st = state[cb, ca]
                row_cubics(coef, cr, ca, st, ty, rc)
                if st == 1:
                    a0, a1, a2, a3 = rc[0, 0], rc[0, 1], rc[0, 2], rc[0, 3]
                    b0, b1, b2, b3 = rc[1, 0], rc[1, 1], rc[1, 2], rc[1, 3]
                    for cc in range(c, c1):
                        tx = (cc + ox) * inv - ca
                        xr[cc] = (((a3 * tx + a2) * tx + a1) * tx + a0) - 0.5
                        yr[cc] = (((b3 * tx + b2) * tx + b1) * tx + b0) - 0.5
                        vr[cc] = True
                        nr[cc] = NEED_DONE
                else:
                    for cc in range(c, c1):
                        tx = (cc + ox) * inv - ca
                        dx = dy = dz = 0.0
                        if st == 2:
                            dx = cubic(rc, 2, tx)
                            dy = cubic(rc, 3, tx)
                            dz = cubic(rc, 4, tx)
                        _store_cell(st, r, cc, k, 0.0, 0.0, dx, dy, dz, xs, ys, valid, need, dirs)
                c = c1
