"""NumPy references of the pyramid's compiled kernels (``src/native/pyramid.cpp``) and of the far footprints the
map marks for it (``neighbour_secants``' ``coarse``), for the tests: the same values, one readable step at a time."""

from __future__ import annotations

import numpy as np


def halve(src: np.ndarray) -> np.ndarray:
    """The next pyramid level of ``src`` (float32 (h, w, C)): each 2x2 block's mean, the two horizontal pairs
    summed first, in float64, rounded once to float32 ((h // 2, w // 2, C))."""
    d = np.asarray(src, dtype=np.float32).astype(np.float64)
    h, w = d.shape[0] // 2 * 2, d.shape[1] // 2 * 2
    d = d[:h, :w]
    return (((d[0::2, 0::2] + d[0::2, 1::2]) + (d[1::2, 0::2] + d[1::2, 1::2])) * 0.25).astype(np.float32)


def far_samples(foot: np.ndarray, valid: np.ndarray, far: float) -> np.ndarray:
    """int64 flat indices of the valid samples whose footprint (float32 sides (..., 4)) has a side longer than
    ``far`` texels, |a|^2 or |b|^2 in float64 beyond far^2 (or not a number): those the pyramid's level_rows sends
    beyond level 0. The kernel's ``coarse`` list holds every one of them."""
    f = np.asarray(foot, np.float32).reshape(-1, 4).astype(np.float64)
    la, lb = f[:, 0] ** 2 + f[:, 1] ** 2, f[:, 2] ** 2 + f[:, 3] ** 2
    far_ = ~((la <= far * far) & (lb <= far * far))
    return np.flatnonzero(np.asarray(valid, bool).reshape(-1) & far_)
