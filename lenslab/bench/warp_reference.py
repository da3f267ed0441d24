"""An accuracy reference for ``lenslab bench warp`` written apart from the engine: float64 supersampling
of a full-sphere equirect into a centred equidistant fisheye, straight from the formulas of
docs/conventions.md, with its own bilinear reconstruction (seam wrapped, rows folded across the poles).

It averages the bilinear reconstruction of the source over each output pixel (``k x k`` stratum
centres), which is what the footprint prefilter approximates; at ``k = 16`` its own error is far below
the 0.3% aim (k = 12 and k = 16 differ by 0.03% relative L1 on forest.exr, measured)."""

from __future__ import annotations

import numpy as np


def fisheye_rays(size: int, fov_deg: float, k: int, rows: slice) -> tuple[np.ndarray, np.ndarray]:
    """Unit rays (float64, (h, size, k*k, 3)) of an equidistant fisheye's stratum centres and validity."""
    y0, y1 = rows.start, rows.stop
    sub = (np.arange(k) + 0.5) / k
    x = (np.arange(size)[None, :, None, None] + sub[None, None, None, :])
    y = (np.arange(y0, y1)[:, None, None, None] + sub[None, None, :, None])
    x, y = np.broadcast_arrays(x, y)
    u = 2.0 * x / size - 1.0
    v = 1.0 - 2.0 * y / size
    r = np.hypot(u, v)
    a = r * np.radians(fov_deg) / 2.0  # equidistant: angle from the axis linear in r
    with np.errstate(invalid="ignore", divide="ignore"):
        s = np.where(r > 0, np.sin(a) / r, 1.0)
    d = np.stack([s * u, s * v, np.cos(a)], axis=-1).reshape(y1 - y0, size, k * k, 3)
    return d, (r <= 1.0).reshape(y1 - y0, size, k * k)


def bilinear_equirect(img: np.ndarray, d: np.ndarray) -> np.ndarray:
    """The equirect ``img`` (H x W x C) read bilinearly (float64) along unit rays ``d`` (..., 3)."""
    h, w = img.shape[:2]
    lon = np.arctan2(d[..., 0], d[..., 2])
    lat = np.arctan2(d[..., 1], np.hypot(d[..., 0], d[..., 2]))
    x = (lon / np.pi + 1.0) * w / 2.0 - 0.5  # index coordinates: pixel centres at whole numbers
    y = (1.0 - lat / (np.pi / 2.0)) * h / 2.0 - 0.5
    i0 = np.floor(x).astype(np.int64)
    j0 = np.floor(y).astype(np.int64)
    tx, ty = x - i0, y - j0
    out = 0.0
    for dj, wy in ((0, 1.0 - ty), (1, ty)):
        for di, wx in ((0, 1.0 - tx), (1, tx)):
            i, j = i0 + di, j0 + dj
            # across a pole: row -1 - j is row j on the opposite meridian
            top, bottom = j < 0, j >= h
            j = np.where(top, -1 - j, np.where(bottom, 2 * h - 1 - j, j))
            i = np.where(top | bottom, i + w // 2, i) % w
            out = out + (wx * wy)[..., None] * img[j, i].astype(np.float64)
    return out


def reference(img: np.ndarray, size: int, fov_deg: float = 180.0, k: int = 16, rows_per_chunk: int = 8):
    """Box average of the bilinear source over every output pixel, premultiplied by coverage (float64)."""
    out = np.zeros((size, size, img.shape[2]))
    for r0 in range(0, size, rows_per_chunk):
        rows = slice(r0, min(size, r0 + rows_per_chunk))
        d, ok = fisheye_rays(size, fov_deg, k, rows)
        vals = np.where(ok[..., None], bilinear_equirect(img, d), 0.0)
        out[rows] = vals.mean(axis=2)
    return out
