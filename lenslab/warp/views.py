"""Sources that see a direction more than once: every sample blends the source lens's weighted views.

A lens whose :meth:`~lenslab.lenses.core.base.Lens.source_view_count` is above 1 (two fisheyes whose
circles overlap) answers :meth:`~lenslab.lenses.core.base.Lens.source_views` with several ``(xy, valid,
weight)`` readings per direction. Each output sample is then the weighted sum of its views' filtered
values, ``sum_k w_k v_k`` (the weights sum to 1 where any view sees the ray), and a pixel's colour
and alpha the mean over its samples, as for a one-view source. The maps are computed exactly, sample
by sample (such a source is made of pieces, which the lattice never interpolates across).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from lenslab.lenses import rotation_between
from lenslab.warp.filters import sample
from lenslab.warp.maps import MapBand


def has_views(lens) -> bool:
    """Whether a source lens reads some directions from more than one place."""
    return int(lens.source_view_count()) > 1


@dataclass
class ViewBand:
    """The map of output rows ``r0:r1`` for a many-view source: one :class:`MapBand` per view and each
    sample's weight in it (float32 ``(h, W, S)``, 0 where that view does not see the ray)."""

    r0: int
    r1: int
    views: list
    weights: list

    @property
    def nbytes(self) -> int:
        return sum(b.nbytes for b in self.views) + sum(w.nbytes for w in self.weights)


def view_band(mapper, r0: int, r1: int, offsets: np.ndarray) -> ViewBand:
    """Every view's map of output rows ``r0:r1`` at sub-pixel ``offsets`` ((S, 2) or (h, W, S, 2))."""
    src, dst = mapper.src, mapper.dst
    offsets = np.asarray(offsets, dtype=np.float64)
    if offsets.ndim == 2:
        offsets = offsets[None, None]
    h, w, n = r1 - r0, mapper.width, offsets.shape[2]
    pts = np.empty((h, w, n, 2), dtype=np.float64)
    pts[..., 0] = np.arange(w, dtype=np.float64)[None, :, None] + offsets[..., 0]
    pts[..., 1] = np.arange(r0, r1, dtype=np.float64)[:, None, None] + offsets[..., 1]
    d, ray = dst.lens.pixel_to_dir(pts)
    r = rotation_between(src, dst)
    if not np.array_equal(r, np.eye(3)):
        d = d @ r.T
    views, weights = [], []
    for xy, ok, wt in src.lens.source_views(d):
        ok = ok & ray
        views.append(MapBand(r0, r1, np.where(ok, xy[..., 0] - 0.5, 0.0).astype(np.float32),
                             np.where(ok, xy[..., 1] - 0.5, 0.0).astype(np.float32), ok))
        weights.append(np.where(ok, wt, 0.0).astype(np.float32))
    return ViewBand(r0, r1, views, weights)


def sample_views(src: np.ndarray, band: ViewBand, border, filter: str, out: np.ndarray, alpha: np.ndarray) -> None:
    """Fill ``out`` (h, W, C) and ``alpha`` (h, W) float32 from a :class:`ViewBand`: per sample the
    weighted sum of its views, per pixel the mean over samples."""
    h, w = alpha.shape
    n = band.views[0].xs.shape[2]
    out[...] = 0.0
    alpha[...] = 0.0
    one = np.empty_like(out)
    one_alpha = np.empty_like(alpha)
    for view, wt in zip(band.views, band.weights):
        for s in range(n):
            ws = wt[..., s]
            if not ws.any():
                continue
            sample(src, np.ascontiguousarray(view.xs[..., s:s + 1]), np.ascontiguousarray(view.ys[..., s:s + 1]),
                   np.ascontiguousarray(view.valid[..., s:s + 1]), border, filter, one, one_alpha)
            out += one * (ws / n)[..., None]
            alpha += one_alpha * (ws / n)
