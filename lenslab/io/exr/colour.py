"""The colour of OpenEXR files: their primaries (the ``chromaticities`` attribute), luminance-chroma
(Y, RY, BY) images back to RGB, and subsampled channels back to full resolution."""

from __future__ import annotations

import numpy as np

#: Rec.709 primaries and D65 white (x, y pairs), OpenEXR's default chromaticities
REC709 = (0.64, 0.33, 0.30, 0.60, 0.15, 0.06, 0.3127, 0.3290)


def upsample(a: np.ndarray, xs: int, ys: int, w: int, h: int, x0: int, y0: int) -> np.ndarray:
    """A subsampled channel back to full resolution by linear interpolation between its samples.

    Stored samples sit at absolute pixel coordinates divisible by the sampling rate.
    """
    out = a.astype(np.float32)
    for axis, s, n, o in ((1, xs, w, x0), (0, ys, h, y0)):
        if s == 1:
            continue
        pos = (np.arange(n) + o) / s - np.ceil(o / s)  # position of each full pixel in sample units
        m = out.shape[axis]
        f = np.floor(pos).astype(np.intp)
        i0, i1 = np.clip(f, 0, m - 1), np.clip(f + 1, 0, m - 1)  # beyond the samples: the nearest one
        t = (pos - f).astype(np.float32)
        a0, a1 = np.take(out, i0, axis=axis), np.take(out, i1, axis=axis)
        shape = (1, n) if axis == 1 else (n, 1)
        out = a0 + (a1 - a0) * t.reshape(shape)
    return out


def primary_matrix(chromaticities) -> np.ndarray:
    """RGB -> XYZ matrix of the primaries and white point (x, y pairs; Y of white = 1)."""
    from lenslab.srgb import colour_science

    colour = colour_science()

    c = np.asarray(chromaticities, dtype=np.float64)
    return colour.normalised_primary_matrix(c[:6].reshape(3, 2), c[6:8])


def luminance_weights(chromaticities=None) -> np.ndarray:
    """(wR, wG, wB): the Y row of the RGB -> XYZ matrix of the chromaticities (Rec.709 if None)."""
    return primary_matrix(chromaticities if chromaticities is not None else REC709)[1]


def yca_to_rgb(y: np.ndarray, ry: np.ndarray, by: np.ndarray, weights) -> np.ndarray:
    """Luminance-chroma (full-resolution Y, RY, BY) -> RGB, float32 H x W x 3.

    ``RY = (R - Y) / Y`` and ``BY = (B - Y) / Y`` as OpenEXR stores them, so ``R = (RY + 1) Y``,
    ``B = (BY + 1) Y`` and G follows from ``Y = wR R + wG G + wB B``.
    """
    wr, wg, wb = (np.float32(v) for v in weights)
    r = (ry + np.float32(1)) * y
    b = (by + np.float32(1)) * y
    g = (y - wr * r - wb * b) / wg
    return np.stack([r, g, b], axis=-1).astype(np.float32, copy=False)
