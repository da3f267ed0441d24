"""The warp's compiled kernels and how they are reached: :mod:`~lenslab.warp.kernels.native` (the C++
samplers and footprint filter, ``lenslab.cxx_kernels``, compiled by ``pip install``),
:mod:`~lenslab.warp.kernels.dispatch` (the numba kernels, compiled on first use and cached) and
:mod:`~lenslab.warp.kernels.reference` (NumPy references of the C++ kernels, for the tests)."""
