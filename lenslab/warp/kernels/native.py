"""The compiled kernels (C++17 through nanobind, ``lenslab.cxx_kernels``, built by ``pip install -e .``).

The samplers (single-tap bilinear, the cached taps, the separable filters), the footprint prefilter and the
map lattice run here: ahead-of-time compiled, they cost nothing on a command's first call (numba compiled
the footprint filter alone for 2.4 s on a new machine, and a plain warp no longer imports numba at all) and
release the GIL, so the engine runs one band of rows per thread. Each has a NumPy reference
(:mod:`lenslab.warp.kernels.reference`, ``lattice_reference``, ``filter_reference``) that the tests hold it
to. ``docs/design.md`` gives the measured figures behind the choice.
"""

from __future__ import annotations

import numpy as np

from lenslab.errors import WarpError
from lenslab.native import extension

def kernels():
    """The extension module; a one-line :class:`WarpError` when this copy of lenslab was installed without it."""
    return extension(WarpError)


def c32(a: np.ndarray) -> np.ndarray:
    """``a`` as a C-contiguous float32 array (no copy when it already is one)."""
    return np.ascontiguousarray(a, dtype=np.float32)


def cbool(a: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(a, dtype=np.bool_)
