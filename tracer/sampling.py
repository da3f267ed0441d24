"""Sample warps and discrete distributions, vectorised over whole batches (float32 in, float32 out).

Every warp takes uniform numbers in [0, 1) and returns the sample with its density, so estimators
divide by exactly the density they drew from.
"""

from __future__ import annotations

import numpy as np

F32 = np.float32
INV_PI = np.float32(1.0 / np.pi)


def dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise dot product of two ``(N, 3)`` arrays (by columns: several times faster than einsum)."""
    return a[:, 0] * b[:, 0] + a[:, 1] * b[:, 1] + a[:, 2] * b[:, 2]


def take(a: np.ndarray, index: np.ndarray) -> np.ndarray:
    """Rows ``a[index]`` (``np.take`` gathers ``(N, 3)`` rows several times faster than fancy indexing)."""
    return np.take(a, index, axis=0)


def normalize(v: np.ndarray) -> np.ndarray:
    """Unit rows of an ``(N, 3)`` array (zero rows stay zero)."""
    n = np.sqrt(dot(v, v))
    return v / np.where(n > 0, n, 1)[:, None]


def frame(n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two tangents ``(s, t)`` completing the unit normals ``n`` to right-handed orthonormal frames.

    The branchless construction of Duff et al. (2017), "Building an orthonormal basis, revisited".
    """
    x, y, z = n[:, 0], n[:, 1], n[:, 2]
    sign = np.where(z >= 0, 1.0, -1.0).astype(n.dtype)
    a = -1.0 / (sign + z)
    b = x * y * a
    s = np.stack([1.0 + sign * x * x * a, sign * b, -sign * x], axis=1)
    t = np.stack([b, sign + y * y * a, -y], axis=1)
    return s, t


def to_world(local: np.ndarray, n: np.ndarray) -> np.ndarray:
    """Directions given in the frame (s, t, n) of each normal, back in world space."""
    s, t = frame(n)
    return local[:, 0:1] * s + local[:, 1:2] * t + local[:, 2:3] * n


def cosine_around(n: np.ndarray, u1: np.ndarray, u2: np.ndarray) -> np.ndarray:
    """World directions with density ``max(0, n . w) / pi`` about the unit normals ``n``.

    A uniform point on the unit sphere centred at the tip of ``n``, seen from the surface point, is
    cosine distributed (the projection of a sphere tangent to the plane is uniform on the disk under
    it, Malley's method in disguise); cheaper than building a frame per normal.
    """
    w = n + uniform_sphere(u1, u2)
    length = np.sqrt(dot(w, w))
    bad = length < 1e-6  # the sphere point opposite the normal: take the normal itself
    w /= np.where(bad, F32(1), length)[:, None]
    if bad.any():
        w[bad] = n[bad]
    return w


def power_cosine(u1: np.ndarray, u2: np.ndarray, exponent: np.ndarray) -> np.ndarray:
    """Local directions with density ``(n + 1) / (2 pi) cos^n(theta)`` about +z."""
    z = u1 ** (1.0 / (exponent + 1.0))
    r = np.sqrt(np.maximum(0.0, 1.0 - z * z))
    phi = (2 * np.pi) * u2
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1).astype(F32)


def uniform_sphere(u1: np.ndarray, u2: np.ndarray) -> np.ndarray:
    """Directions with density ``1 / (4 pi)`` over the whole sphere."""
    z = 1.0 - 2.0 * u1
    r = np.sqrt(np.maximum(0.0, 1.0 - z * z))
    phi = (2 * np.pi) * u2
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1).astype(F32)


def uniform_triangle(u1: np.ndarray, u2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Barycentric weights ``(b1, b2)`` uniform over a triangle (square-root warp)."""
    su = np.sqrt(u1)
    return 1.0 - su, u2 * su


def power_heuristic(pdf_a: np.ndarray, pdf_b: np.ndarray) -> np.ndarray:
    """Veach's power heuristic (beta = 2) weight of strategy ``a`` against ``b``."""
    a2 = pdf_a * pdf_a
    b2 = pdf_b * pdf_b
    s = a2 + b2
    return np.where(s > 0, a2 / np.where(s > 0, s, 1), 0).astype(F32)


class Distribution1D:
    """A piecewise-constant distribution over ``n`` bins of ``[0, 1)`` (or a discrete one over bins)."""

    def __init__(self, weights: np.ndarray):
        w = np.asarray(weights, dtype=np.float64).ravel()
        if w.size == 0 or not np.all(np.isfinite(w)) or np.any(w < 0):
            raise ValueError("distribution weights must be finite, non-negative, and at least one")
        self.n = w.size
        self.total = float(w.sum())
        if self.total <= 0:
            w = np.ones_like(w)
            self.total = 0.0
        self.pmf = w / w.sum()
        self.cdf = np.concatenate([[0.0], np.cumsum(self.pmf)])
        self.cdf[-1] = 1.0

    def sample_discrete(self, u: np.ndarray) -> np.ndarray:
        """Bin indices (int64) drawn with probability ``pmf``."""
        # side="right" skips empty bins (their CDF step is flat); callers still check the density
        # they get, for the rounding-level chance of landing past the last non-empty bin
        return np.clip(np.searchsorted(self.cdf, u, side="right") - 1, 0, self.n - 1)

    def sample_continuous(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Positions in ``[0, n)`` (bin index plus the offset inside it) and bin indices."""
        idx = self.sample_discrete(u)
        lo = self.cdf[idx]
        width = self.pmf[idx]
        frac = np.where(width > 0, (u - lo) / np.where(width > 0, width, 1), 0.5)
        return idx + np.clip(frac, 0.0, np.nextafter(1.0, 0.0)), idx
