"""What an output sees of a source: the criterion auto-scale searches on (see :mod:`lenslab.fit.autoscale`).

:class:`Criterion` counts the output's holes (``fill``: pixels whose ray exists but falls outside the
source) or the source's cropped samples (``cover``: source samples, pixel corners and the exact rim of
the source's valid region that the output does not show), on a sparse active set first and on every
sample to verify.
"""

from __future__ import annotations

import numpy as np

from lenslab.lenses import Camera, rotation_between, sample_offsets
from lenslab.lenses.core.base import Lens

SPARSE = 8  # the sparse pre-check tests every SPARSE-th pixel (plus the border ring)


def _positions(width: int, height: int, stride: int, samples: int) -> np.ndarray:
    """Sub-pixel sample positions of the border ring plus every ``stride``-th pixel: (n, 2)."""
    xs = np.arange(width)
    ys = np.arange(height)
    if stride > 1:
        xs = np.unique(np.concatenate([xs[::stride], [width - 1]]))
        ys = np.unique(np.concatenate([ys[::stride], [height - 1]]))
    gx, gy = np.meshgrid(xs, ys)
    pix = np.stack([gx.ravel(), gy.ravel()], axis=-1).astype(np.float64)
    if stride > 1:  # the full border ring too
        ring = np.concatenate([
            np.stack([np.arange(width), np.zeros(width)], -1), np.stack([np.arange(width), np.full(width, height - 1)], -1),
            np.stack([np.zeros(height), np.arange(height)], -1), np.stack([np.full(height, width - 1), np.arange(height)], -1),
        ]).astype(np.float64)
        pix = np.unique(np.concatenate([pix, ring]), axis=0)
    off = sample_offsets(samples, (), None)  # (S, 2) in [0, 1)
    return (pix[:, None, :] + off[None, :, :]).reshape(-1, 2)


class Criterion:
    """Counts holes (fill) or cropped source samples (cover) at a scale.

    Tests run on an *active* set (the border ring and a sparse grid, plus every sample that has
    failed a full check so far); :meth:`full_failures` checks every sample.
    """

    def __init__(self, src: Camera, dst: Camera, mode: str, samples: int):
        self.src, self.dst, self.mode = src, dst, mode
        self.rot = rotation_between(src, dst)  # dst camera space -> src camera space
        w, h = dst.size if mode == "fill" else src.size
        self.samples = samples
        self.full = _positions(w, h, 1, samples)
        self.active = _positions(w, h, SPARSE, samples)
        self.evaluations = 0
        self.full_evaluations = 0
        if mode == "cover":  # source rays, in the output's camera space
            d, ok = src.lens.pixel_to_dir(self.full)
            self.full_ok = ok
            self.full_dirs = np.where(ok[:, None], d @ self.rot, 0.0)
            d, ok = src.lens.pixel_to_dir(self.active)
            outline = _outline_dirs(src.lens) @ self.rot  # the pixels' corners and the exact rim
            self.extra_dirs = outline
            self.active_dirs = np.concatenate([d[ok] @ self.rot, outline])

    def _seen(self, lens: Lens, pts: np.ndarray | None, dirs: np.ndarray | None) -> np.ndarray:
        if self.mode == "fill":
            d, ok = lens.pixel_to_dir(pts)
            seen = np.ones(len(pts), dtype=bool)
            seen[ok] = self.src.lens.dir_to_pixel(d[ok] @ self.rot.T)[1]
            return seen
        return lens.dir_to_pixel(dirs)[1]

    def count(self, lens: Lens | None) -> int:
        """Failing samples of the active set (a huge number where the model refuses the scale)."""
        self.evaluations += 1
        if lens is None:
            return 1 << 40
        if self.mode == "fill":
            return int((~self._seen(lens, self.active, None)).sum())
        return int((~self._seen(lens, None, self.active_dirs)).sum())

    def full_failures(self, lens: Lens) -> np.ndarray:
        """Mask over every sample of the ones that fail (for cover, then over the outline's points)."""
        self.full_evaluations += 1
        if self.mode == "fill":
            return ~self._seen(lens, self.full, None)
        fail = np.zeros(len(self.full), dtype=bool)
        fail[self.full_ok] = ~self._seen(lens, None, self.full_dirs[self.full_ok])
        return np.concatenate([fail, ~self._seen(lens, None, self.extra_dirs)])

    def activate(self, fail: np.ndarray) -> None:
        """Add failing samples to the active set (so the next search respects them)."""
        n = len(self.full)
        self.active = np.concatenate([self.active, self.full[fail[:n]]])
        if self.mode == "cover":
            self.active_dirs = np.concatenate([self.active_dirs, self.full_dirs[fail[:n]]])

    def pixels(self, lens: Lens | None) -> int:
        """Number of *pixels* (not samples) that fail, on every pixel."""
        if lens is None:
            return -1
        return int(self.full_failures(lens)[: len(self.full)].reshape(-1, self.samples).any(axis=1).sum())


def _outline_dirs(lens: Lens, steps: int = 40) -> np.ndarray:
    """Directions of the source's pixel corners and of the exact rim of its valid region: ``(n, 3)``.

    Showing all of a source means showing each pixel's whole area, up to where the lens stops seeing:
    a 180-degree fisheye's rim pixels reach 90 degrees off its axis, which no perspective view shows.
    The rim is found on every pixel edge whose two corners disagree, by bisection to ``2**-steps`` px.
    """
    w, h = lens.width, lens.height
    gx, gy = np.meshgrid(np.arange(w + 1, dtype=np.float64), np.arange(h + 1, dtype=np.float64))
    corners = np.stack([gx, gy], axis=-1)
    d, ok = lens.pixel_to_dir(corners.reshape(-1, 2))
    ok = ok.reshape(h + 1, w + 1)
    found = [d[ok.ravel()]]
    for axis in (0, 1):  # edges along y, then along x
        a = corners[:-1, :] if axis == 0 else corners[:, :-1]
        b = corners[1:, :] if axis == 0 else corners[:, 1:]
        oka = ok[:-1, :] if axis == 0 else ok[:, :-1]
        okb = ok[1:, :] if axis == 0 else ok[:, 1:]
        cut = oka != okb
        if not cut.any():
            continue
        inside = np.where(oka[cut][:, None], a[cut], b[cut])  # the valid end
        outside = np.where(oka[cut][:, None], b[cut], a[cut])
        for _ in range(steps):
            mid = 0.5 * (inside + outside)
            good = lens.pixel_to_dir(mid)[1]
            inside = np.where(good[:, None], mid, inside)
            outside = np.where(good[:, None], outside, mid)
        dd, okk = lens.pixel_to_dir(inside)
        found.append(dd[okk])
    return np.concatenate(found)
