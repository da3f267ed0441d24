"""How the compiled samplers read a map position (``clamp_pos`` in ``src/native/kernels.h``), for the NumPy
references of every kernel."""

from __future__ import annotations

import numpy as np

FAR = np.float32(2.0**40)  # a position beyond +-2^40 (inf included) is read at +-2^40, NaN at -2^40 (clamp_pos)


def clamp_pos(v):
    """Map positions as the samplers read them (``clamp_pos`` in ``src/native/kernels.h``): an edge pixel for
    1e30, inf or NaN, and no float converted to an integer out of range."""
    v = np.asarray(v, dtype=np.float32)
    return np.where(v >= -FAR, np.minimum(v, FAR), -FAR).astype(np.float32)
