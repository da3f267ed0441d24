"""The lens models' compiled kernels: C++17 in the extension ``lenslab.cxx_kernels`` (``src/native/lens_*``),
built by ``pip install -e .``, so no lens compiles anything on a machine's first warp.

Direction -> pixel of the equirect, perspective, Hammer, cube map, equi-angular cube map, fisheye, little-planet,
dual-fisheye, cylinder (central, equal-area, Mercator), sinusoidal, Pannini and Brown-distorted and swirled pinhole
models (their :class:`~lenslab.lenses.core.protocol.PixelKernel`, which the warp engine and
:meth:`Lens.dir_to_pixel` run), the calibrated models' projections and solved inverses, OCamCalib's solved
projection, the lensfun profiles' direction -> pixel and the solved sides of the division, Brown and tan-fold
fisheye models. Each has a NumPy reference in :mod:`lenslab.lenses.formulas.reference` that the tests hold it to.

Pixel -> direction of the fisheye, the little planet, the cylinders, Pannini, the perspective and the equi-angular
cube map (their :class:`~lenslab.lenses.core.protocol.DirKernel`, which :meth:`Lens.pixel_to_dir` runs, so the
warp's exact map does): ``src/native/lens_dirs.cpp`` (the cube map's in ``lens_cubemap.cpp``).
"""

from __future__ import annotations

import numpy as np

from lenslab.errors import LensError
from lenslab.native import extension

def lens_kernels():
    """The extension module; a one-line :class:`LensError` when this copy of lenslab was installed without it."""
    return extension(LensError)


def project_kernel(kern, d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Pixel positions (float64 ``(..., 2)``) and validity (bool ``(...)``) of directions ``d`` (``(..., 3)``,
    any length) through a lens's :class:`~lenslab.lenses.core.protocol.PixelKernel`: zero and non-finite
    directions are invalid, and every invalid position is 0. The kernel releases the GIL, so bands of a warp
    project on several threads."""
    flat = np.ascontiguousarray(d, dtype=np.float64).reshape(-1, 3)
    xy = np.empty((len(flat), 2), dtype=np.float64)
    valid = np.empty(len(flat), dtype=np.bool_)
    kern.fn(flat, kern.params, xy, valid)
    return xy.reshape(d.shape[:-1] + (2,)), valid.reshape(d.shape[:-1])


def unproject_kernel(kern, xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit directions (float64 ``(..., 3)``) and validity (bool ``(...)``) of pixel positions ``xy``
    (``(..., 2)``, any length) through a lens's :class:`~lenslab.lenses.core.protocol.DirKernel`: non-finite
    pixels have no ray, and every direction without one is 0. The kernel releases the GIL."""
    flat = np.ascontiguousarray(xy, dtype=np.float64).reshape(-1, 2)
    d = np.empty((len(flat), 3), dtype=np.float64)
    valid = np.empty(len(flat), dtype=np.bool_)
    kern.fn(flat, kern.params, d, valid)
    return d.reshape(xy.shape[:-1] + (3,)), valid.reshape(xy.shape[:-1])


#: the steps of Lens.pixel_to_dir that a model's compiled pixel -> dir stands for
DIR_STEPS = ("pixel_to_dir", "_uv_pixel_to_dir", "pixel_to_uv", "uv_to_dir")


def dir_kernel_holds(lens, model: type, steps: tuple[str, ...] = ()) -> bool:
    """Whether ``model``'s compiled ``pixel -> dir`` still describes ``lens``: a subclass that changed one of
    :data:`DIR_STEPS` (or of the model's own ``steps``) has no kernel."""
    return all(getattr(type(lens), name) is getattr(model, name) for name in DIR_STEPS + tuple(steps))


#: the steps of Lens.dir_to_pixel that a model's compiled dir -> pixel stands for
KERNEL_STEPS = ("dir_to_pixel", "dir_to_uv", "uv_to_pixel", "snap_to_image", "edge_slack")


def kernel_holds(lens, model: type, steps: tuple[str, ...] = ()) -> bool:
    """Whether ``model``'s compiled kernel still describes ``lens``: a subclass that changed one of
    :data:`KERNEL_STEPS` (or of the model's own ``steps``) has no kernel (its :meth:`dir_to_pixel` runs its own
    NumPy steps)."""
    return all(getattr(type(lens), name) is getattr(model, name) for name in KERNEL_STEPS + tuple(steps))
