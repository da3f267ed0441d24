"""The lens models' compiled kernels: C++17 in the extension ``lenslab.cxx_kernels`` (``src/native/lens_*``),
built by ``pip install -e .``, so no lens compiles anything on a machine's first warp.

Direction -> pixel of the equirect (the warp engine's :class:`~lenslab.lenses.core.protocol.PixelKernel`), the
calibrated models' projections and solved inverses, OCamCalib's solved projection, the lensfun profiles'
direction -> pixel and the solved sides of the division, Brown and tan-fold fisheye models. Each has a NumPy
reference in :mod:`lenslab.lenses.formulas.reference` that the tests hold it to.
"""

from __future__ import annotations

from lenslab.errors import LensError

_module = None


def lens_kernels():
    """The extension module; a one-line error when this copy of lenslab was installed without it."""
    global _module
    if _module is None:
        try:
            from lenslab import cxx_kernels
        except ImportError as exc:  # a source tree used without installing it
            raise LensError("lenslab's compiled kernels are not built: install lenslab with `pip install -e .` "
                            f"(needs a C++17 compiler and CMake) ({exc})") from None
        _module = cxx_kernels
    return _module
