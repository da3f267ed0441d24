"""The map lattice's arithmetic: ghost nodes beyond the valid region, Catmull-Rom coefficients per cell,
and the kernels that evaluate a band of the map from them (see :mod:`lenslab.warp.maps`).

The kernels are C++ (:mod:`lenslab.warp.kernels.native`), compiled when lenslab is installed, so a warp
neither compiles nor imports numba for its map; their NumPy references are in
:mod:`lenslab.warp.kernels.lattice_reference`, with the same bits. A lens's own compiled ``dir -> pixel``
kernel is C++ too (:mod:`lenslab.lenses.core.native`).
"""

from __future__ import annotations

import numpy as np

from lenslab.warp.kernels import native

NEED_DONE, NEED_EXACT, NEED_PROJECT = 0, 1, 2  # what a sample still needs after the lattice kernels


def ghost_nodes(nx, ny, valid, wrap):
    """Fill invalid lattice nodes next to valid ones by extrapolation (an x pass, then a y pass):
    quadratic from three valid neighbours in a line, linear from two (never from nodes within three
    of the lattice's far edge, as before: the first and last three nodes along the pass are skipped).

    Returns the filled x and y node values (C-contiguous float64) and which nodes now have a value.
    """
    gx, gy = np.empty(np.shape(nx)), np.empty(np.shape(ny))
    return gx, gy, ghost_nodes_into(nx, ny, valid, wrap, gx, gy)


def ghost_nodes_into(nx, ny, valid, wrap, gx: np.ndarray, gy: np.ndarray) -> np.ndarray:
    """:func:`ghost_nodes` written into ``gx`` and ``gy`` (C-contiguous float64 arrays of the nodes' shape, e.g. two
    planes of the lattice's stacked nodes); returns which nodes now have a value. The two components share the
    extrapolation's decisions (they depend on ``valid`` alone) and, with ``wrap`` 0, its arithmetic: any two
    components of one set of nodes may be filled in one call."""
    np.copyto(gx, nx)
    np.copyto(gy, ny)
    have = np.array(valid, dtype=np.bool_, order="C")
    native.kernels().ghost_pass(gx, gy, have, float(wrap))
    return have


def lattice_grid(nx, ny, tx: float, ty: float, wrap: float) -> tuple[np.ndarray, np.ndarray]:
    """The Catmull-Rom interpolant of every cell of the node lattice ``nx, ny`` (float64 (rows, cols)) at
    the cell fraction ``(tx, ty)``: two float64 ``(rows - 3, cols - 3)`` arrays; x unwrapped by ``wrap``."""
    nx = np.ascontiguousarray(nx, dtype=np.float64)
    ny = np.ascontiguousarray(ny, dtype=np.float64)
    ox = np.empty((nx.shape[0] - 3, nx.shape[1] - 3))
    oy = np.empty_like(ox)
    native.kernels().lattice_grid(nx, ny, float(tx), float(ty), float(wrap), ox, oy)
    return ox, oy


def cell_coefficients(nodes, state, cb0: int, cb1: int, wrap: float, coef: np.ndarray) -> None:
    """Fill ``coef[row, ca, q]`` = CR^T P CR (``c[b, a]`` of tx^a ty^b; float64 ``(cb1 - cb0, ncx, K, 4, 4)``)
    for the cells that interpolate: x and y for state 1, the direction for state 2; the x stencil unwrapped
    across the seam. ``nodes``: float64 ``(K, ncy + 3, ncx + 3)``; ``state``: int8 ``(ncy, ncx)``."""
    native.kernels().cell_coefficients(np.ascontiguousarray(nodes, dtype=np.float64),
                                       np.ascontiguousarray(state, dtype=np.int8), int(cb0), int(cb1), float(wrap),
                                       coef)


def lattice_eval(coef, state, cb0, step, r0, offs, xs, ys, valid, need, dirs) -> None:
    """The map of a band from the lattice, per-sample offsets ``offs`` (h, W, S, 2): index coordinates,
    validity, and per sample what it still needs (``NEED_*``; ``dirs`` holds the directions to project).

    ``xs, ys`` float32, ``valid`` bool, ``need`` int8 ``(h, W, S)`` and ``dirs`` float64 ``(h, W, S, 3)`` are
    written in place; ``coef`` holds cell rows ``cb0:`` (:func:`cell_coefficients`)."""
    native.kernels().lattice_eval(coef, state, int(cb0), float(step), int(r0), np.ascontiguousarray(offs, np.float64),
                                  xs, ys, valid, need, dirs)


def lattice_rows(coef, state, cb0, inv, r0, offs, xs, ys, valid, need, dirs) -> None:
    """:func:`lattice_eval` for offsets shared by every pixel (``offs`` (1, 1, S, 2); ``inv`` = 1 / step): along
    a row of samples ty is fixed, so each cell's bicubic collapses to a cubic in tx, made once per cell and
    row, and a row is walked cell by cell (the samples of an interpolating cell are one vectorised loop)."""
    native.kernels().lattice_rows(coef, state, int(cb0), float(inv), int(r0), np.ascontiguousarray(offs, np.float64),
                                  xs, ys, valid, need, dirs)


def place(at, xy, v, xs, ys, valid) -> None:
    """Write mapped samples into a band's flat maps: at flat positions ``at`` (int64), ``xs``/``ys`` (float32) get
    the index coordinates ``xy - 0.5`` (``xy`` float64 (n, 2) source pixels) where ``v``, else 0, and ``valid``
    gets ``v`` (one compiled pass, no temporaries; reference :func:`lenslab.warp.kernels.lattice_reference.place`)."""
    native.kernels().place(np.ascontiguousarray(at, np.int64), np.ascontiguousarray(xy, np.float64),
                           np.ascontiguousarray(v, np.bool_), xs, ys, valid)
