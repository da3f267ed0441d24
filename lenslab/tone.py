"""Tone curves (placeholder: only ``clamp`` until the full set lands)."""

from __future__ import annotations

import numpy as np


def tonemap(image, curve: str = "clamp", exposure: float = 0.0, **params):
    x = np.nan_to_num(np.asarray(image, dtype=np.float32), nan=0.0, posinf=1.0, neginf=0.0)
    x = np.maximum(x, 0) * np.float32(2.0 ** float(exposure))
    return np.minimum(x, 1.0)
