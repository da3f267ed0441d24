"""The compiled extension ``lenslab.cxx_kernels`` (C++17 through nanobind, built by ``pip install -e .``),
loaded once for every package that runs its kernels (the lenses' models, the warp's samplers)."""

from __future__ import annotations

_module = None


def extension(error: type[Exception] = ImportError):
    """The extension module; ``error`` (the caller's error type) with a one-line message when this copy of
    lenslab was installed without it."""
    global _module
    if _module is None:
        try:
            from lenslab import cxx_kernels
        except ImportError as exc:  # a source tree used without installing it
            raise error("lenslab's compiled kernels are not built: install lenslab with `pip install -e .` "
                        f"(needs a C++17 compiler and CMake) ({exc})") from None
        _module = cxx_kernels
    return _module
