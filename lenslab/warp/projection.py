"""Directions into a source lens through the lens's compiled ``dir -> pixel``
(:class:`~lenslab.lenses.core.protocol.PixelKernel`): the engine asks the lens for its kernel and runs it,
never reading the lens's name. The kernels are C++ (``lenslab.cxx_kernels``), compiled when lenslab is
installed, so a first warp compiles nothing; each releases the GIL, so bands project on several threads.
"""

from __future__ import annotations

import numpy as np


def project_kernel(kern, d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Pixel positions (float64 ``(..., 2)``) and validity (bool ``(...)``) of directions ``d`` (``(..., 3)``,
    any length) through ``kern``: zero and non-finite directions are invalid, and their positions 0."""
    flat = np.ascontiguousarray(d, dtype=np.float64).reshape(-1, 3)
    xy = np.empty((len(flat), 2), dtype=np.float64)
    valid = np.empty(len(flat), dtype=np.bool_)
    kern.fn(flat, np.ascontiguousarray(kern.params, dtype=np.float64), xy, valid)
    return xy.reshape(d.shape[:-1] + (2,)), valid.reshape(d.shape[:-1])
