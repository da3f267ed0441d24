"""Arrays of points and directions as every lens takes and returns them: float64, the coordinate on the last
axis, unit directions, and values zeroed where they are not valid (no NaN or inf leaves a model)."""

from __future__ import annotations

import numpy as np

from lenslab.errors import LensError

FLOAT = np.float64


def as_points(a, last: int, what: str) -> np.ndarray:
    """Return ``a`` as a float64 array whose last axis has length ``last``."""
    arr = np.asarray(a, dtype=FLOAT)
    if arr.ndim == 0 or arr.shape[-1] != last:
        raise LensError(f"{what} must have shape (..., {last}), got {arr.shape}")
    return arr


def normalize(d: np.ndarray) -> np.ndarray:
    """Unit vectors along the last axis (zero vectors stay zero)."""
    n2 = np.einsum("...i,...i->...", d, d)
    with np.errstate(invalid="ignore", divide="ignore"):
        out = d / np.sqrt(n2)[..., None]
    zero = ~(n2 > 0)
    if zero.any():
        out[zero] = 0.0
    return out


def clean(values: np.ndarray, valid: np.ndarray, inplace: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Zero the entries flagged invalid or non-finite, and flag non-finite ones invalid.

    With ``inplace=True`` the zeros are written into ``values`` itself (for arrays the caller owns).
    """
    # one pass finds non-finite rows: a NaN or inf in any component makes the squared norm non-finite
    with np.errstate(over="ignore", invalid="ignore"):
        finite = np.isfinite(np.einsum("...i,...i->...", values, values))
    valid = np.logical_and(valid, finite)
    if not inplace:
        values = values.copy()
    np.copyto(values, 0.0, where=~valid[..., None])
    return values, valid
