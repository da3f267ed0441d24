"""An ST map as a warp holds it, and the source positions of a band of its rows.

:func:`lenslab.stmap.read_st_map` gives a map as an ``h x w x 4`` float32 image (s, t, 0, A): for a map of a large
output as much memory as the output's own float32 RGBA image. A warp keeps :func:`packed` instead, its s and t
(float32, NaN where the map has no ray: half of it), and makes the source positions of each band of rows as it draws
that band (:func:`band_positions`), with the same arithmetic as a map of source positions of the whole output made
first (:func:`lenslab.stmap.source_positions` then :func:`lenslab.warp.warp_with_map`), so the same bits.
"""

from __future__ import annotations

import numpy as np

#: rows of a map packed at a time (the temporaries of one band, not of the map's size)
PACK_ROWS = 256


def packed(st: np.ndarray) -> np.ndarray:
    """An ``h x w x 4`` (s, t, 0, A) map -> float32 ``h x w x 2`` (s, t), NaN where ``A`` is 0; a map already packed
    is returned as it is.

    >>> st = np.array([[[0.25, 0.5, 0.0, 1.0], [0.0, 0.0, 0.0, 0.0]]], np.float32)
    >>> packed(st).tolist()
    [[[0.25, 0.5], [nan, nan]]]
    """
    if st.shape[2] == 2:
        return st
    h, w = st.shape[:2]
    out = np.empty((h, w, 2), np.float32)
    for r0 in range(0, h, PACK_ROWS):
        rows, band = st[r0:r0 + PACK_ROWS], out[r0:r0 + PACK_ROWS]
        band[...] = rows[..., :2]
        band[~(rows[..., 3] > 0.5)] = np.nan
    return out


def unpacked(st: np.ndarray) -> np.ndarray:
    """A :func:`packed` map -> the ``h x w x 4`` (s, t, 0, A) image :func:`lenslab.stmap.read_st_map` gives (s = t = 0
    where A is 0); an ``h x w x 4`` map is returned as it is.

    >>> st = np.array([[[0.25, 0.5, 0.0, 1.0], [0.0, 0.0, 0.0, 0.0]]], np.float32)
    >>> bool(np.array_equal(unpacked(packed(st)), st))
    True
    """
    if st.shape[2] != 2:
        return st
    ok = valid(st)
    full = np.zeros(st.shape[:2] + (4,), np.float32)
    full[..., :2] = np.where(ok[..., None], st, np.float32(0.0))
    full[..., 3] = ok
    return full


def valid(rows: np.ndarray) -> np.ndarray:
    """Where rows of a map (``h x w x 4`` or :func:`packed`) have a ray."""
    return rows[..., 3] > 0.5 if rows.shape[2] >= 4 else ~np.isnan(rows[..., 0])


def band_positions(st: np.ndarray, size: tuple[int, int], r0: int, r1: int):
    """``(xs, ys, ok)`` of map rows ``r0:r1`` for a source of ``size`` (w, h): float32 index coordinates of the source
    positions (s W - 1/2 and (1 - t) H - 1/2, worked in float64, 0 where there is none) and where there is one.

    >>> st = np.array([[[0.25, 0.5, 0.0, 1.0], [0.0, 0.0, 0.0, 0.0]]], np.float32)
    >>> [a.tolist() for a in band_positions(st, (8, 4), 0, 1)]
    [[[1.5, 0.0]], [[1.5, 0.0]], [[True, False]]]
    """
    sw, sh = size
    rows = st[r0:r1]
    with np.errstate(invalid="ignore", over="ignore"):
        xs = (rows[..., 0].astype(np.float64) * sw).astype(np.float32) - np.float32(0.5)
        ys = ((1.0 - rows[..., 1].astype(np.float64)) * sh).astype(np.float32) - np.float32(0.5)
    ok = np.isfinite(xs) & np.isfinite(ys) & valid(rows)
    xs[~ok] = 0.0
    ys[~ok] = 0.0
    return xs, ys, ok


__all__ = ["packed", "unpacked", "valid", "band_positions"]
