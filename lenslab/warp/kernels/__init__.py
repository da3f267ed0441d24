"""The warp's compiled kernels and how they are reached: :mod:`~lenslab.warp.kernels.native` (the C++ kernels,
``lenslab.cxx_kernels``, compiled by ``pip install``: the samplers, the footprint filter, the map lattice),
:mod:`~lenslab.warp.kernels.dispatch` (threads, and the few numba kernels left, compiled on first use) and
the NumPy references of the C++ kernels, for the tests (:mod:`~lenslab.warp.kernels.reference`,
:mod:`~lenslab.warp.kernels.lattice_reference`, :mod:`~lenslab.warp.kernels.filter_reference`)."""
