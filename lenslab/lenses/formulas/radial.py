"""Radial polynomials ``r_d = r_u * P(r_u)`` and their exact inverse, in float64.

lensfun states every radial model this way (Hugin's conventions): distortion poly3
``P = 1 - k1 + k1 r^2``, poly5 ``P = 1 + k1 r^2 + k2 r^4``, ptlens ``P = a r^3 + b r^2 + c r + (1-a-b-c)``,
and transverse chromatic aberration ``P = v + c r + b r^2`` (linear: ``P = k``). A :class:`Radial`
holds the coefficients of ``P`` in rising powers of ``r``, maps ``r_u -> r_d`` and back, and knows the
radius where the map stops rising (beyond it a model has no inverse: those points are flagged).

>>> Radial((1.0, 0.0, 0.1)).forward(np.array([0.5, 1.0])).tolist()   # r (1 + 0.1 r^2)
[0.5125, 1.1]
>>> round(float(Radial((1.0, 0.0, 0.1)).inverse(np.array([1.1]))[0][0]), 12)
1.0
"""

from __future__ import annotations

import numpy as np

#: furthest radius (in units of half the shorter side) any model is asked about
R_LIMIT = 64.0


class Radial:
    """``r -> r * sum(c[i] r^i)``; ``coeffs`` in rising powers (float64)."""

    def __init__(self, coeffs):
        c = np.trim_zeros(np.asarray(coeffs, dtype=np.float64), "b")
        self.coeffs = c if c.size else np.zeros(1)
        # f(r) = r P(r) = sum c_i r^(i+1); f'(r) = sum (i+1) c_i r^i
        self._f = np.concatenate([[0.0], self.coeffs])  # rising powers of f
        self._df = self.coeffs * np.arange(1, self.coeffs.size + 1)
        self.r_max = self._rising_limit()
        self.rd_max = float(self.forward(np.array(self.r_max))) if np.isfinite(self.r_max) else np.inf
        self._table = None

    @property
    def identity(self) -> bool:
        return self.coeffs.size == 1 and self.coeffs[0] == 1.0

    def _rising_limit(self) -> float:
        """Smallest r > 0 where f'(r) = 0 (f rises on [0, r_max]), within :data:`R_LIMIT`; inf when f'
        stays positive there. Found on a fine grid, then bisected (robust for any coefficients)."""
        if not self._df[0] > 0:
            return 0.0
        grid = np.linspace(0.0, R_LIMIT, 8193)
        with np.errstate(all="ignore"):
            fails = np.flatnonzero(~(np.polynomial.polynomial.polyval(grid, self._df) > 0))
        if not fails.size:
            return np.inf
        lo, hi = grid[fails[0] - 1], grid[fails[0]]
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            if np.polynomial.polynomial.polyval(mid, self._df) > 0:
                lo = mid
            else:
                hi = mid
        return float(lo)

    def scale(self, r: np.ndarray) -> np.ndarray:
        """``P(r)``."""
        return np.polynomial.polynomial.polyval(r, self.coeffs)

    def forward(self, r: np.ndarray) -> np.ndarray:
        """``r_d = r P(r)``."""
        return r * self.scale(r)

    def valid_forward(self, r: np.ndarray) -> np.ndarray:
        """Radii on the rising branch (where the model is one-to-one)."""
        return (r >= 0) & (r <= min(self.r_max, R_LIMIT))

    def inverse(self, rd: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``r_u`` with ``r_u P(r_u) = r_d`` on the rising branch, and validity (float64).

        The project's bracketed Newton (:func:`lenslab.lenses.formulas.solve.invert_increasing`) on
        ``[0, r_max]``; radii beyond the branch's top and unconverged ones are invalid.
        """
        from lenslab.lenses.formulas.solve import inverse_table, invert_increasing

        rd = np.asarray(rd, dtype=np.float64)
        if self.identity:
            return rd.copy(), np.isfinite(rd) & (rd >= 0)
        hi_r = min(self.r_max, R_LIMIT)
        top = float(self.forward(np.array(hi_r)))
        # the top of the branch (the fold, where f' = 0) itself: a radius computed there in another order
        # of rounding may come out a few ulps above f(r_max); it is the fold, not beyond it
        valid = np.isfinite(rd) & (rd >= 0) & (rd <= top * (1.0 + 8.0 * np.finfo(np.float64).eps))
        out = np.zeros(rd.shape, dtype=np.float64)
        t = np.minimum(rd[valid], top)
        if t.size:
            def f(x):
                return self.forward(x), np.polynomial.polynomial.polyval(x, self._df)

            if self._table is None:  # starting guesses within ~1e-6: Newton then needs two or three steps
                self._table = inverse_table(f, hi_r)
            table, step = self._table
            x0 = np.interp(t / step, np.arange(table.size, dtype=np.float64), table)
            r, ok = invert_increasing(f, t, 0.0, hi_r, x0)
            out[valid] = np.where(ok, r, 0.0)
            valid[valid] = ok
        return out, valid


def scale_points(q: np.ndarray, radial: Radial, invert: bool) -> tuple[np.ndarray, np.ndarray]:
    """Move 2-D points ``q`` (float64 ``(..., 2)``, centred, normalised) along their radius by
    ``radial`` (``invert``: by its inverse). The centre stays; invalid points come back 0."""
    r = np.hypot(q[..., 0], q[..., 1])
    if invert:
        r2, ok = radial.inverse(r)
    else:
        ok = radial.valid_forward(r)
        r2 = np.where(ok, radial.forward(np.where(ok, r, 0.0)), 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        k = np.where(r > 0, r2 / r, radial.coeffs[0] if not invert else 1.0 / radial.coeffs[0])
    out = q * k[..., None]
    out[~ok] = 0.0
    return out, ok
