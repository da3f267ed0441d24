"""The lens models' compiled kernels: C++17 in the extension ``lenslab.cxx_kernels`` (``src/native/lens_*``),
built by ``pip install -e .``, so no lens compiles anything on a machine's first warp.

Direction -> pixel of the equirect, perspective, Hammer, cube map, equi-angular cube map, fisheye, little-planet,
dual-fisheye, cylinder (central, equal-area, Mercator), sinusoidal, Pannini and Brown-distorted and swirled pinhole
models (their :class:`~lenslab.lenses.core.protocol.PixelKernel`, which the warp engine and
:meth:`Lens.dir_to_pixel` run), the calibrated models' projections and solved inverses, OCamCalib's solved
projection, the lensfun profiles' direction -> pixel and the solved sides of the division, Brown and tan-fold
fisheye models. Each has a NumPy reference in :mod:`lenslab.lenses.formulas.reference` that the tests hold it to.

Pixel -> direction of the equirect, the fisheye, the little planet, the cylinders, Pannini, the perspective and the
equi-angular cube map (their :class:`~lenslab.lenses.core.protocol.DirKernel`, which :meth:`Lens.pixel_to_dir` runs,
so the warp's exact map does): ``src/native/lens_dirs.cpp`` (the cube map's in ``lens_cubemap.cpp``).

Every model calls them the same way: :func:`run_rows` passes the points as float64 rows and shapes the outputs back,
and :func:`dir_to_pixel_through` and :func:`pixel_to_dir_through` choose between a model's kernel and its NumPy steps.
"""

from __future__ import annotations

import numpy as np

from lenslab.errors import LensError
from lenslab.lenses.core.arrays import as_points
from lenslab.native import extension

def lens_kernels():
    """The extension module; a one-line :class:`LensError` when this copy of lenslab was installed without it."""
    return extension(LensError)


def run_rows(points: np.ndarray, width: int, fill) -> tuple[np.ndarray, np.ndarray]:
    """Run a compiled row kernel over ``points`` (``(..., k)``): ``fill(flat, out, valid)`` gets the points as
    C-contiguous float64 rows ``(n, k)`` and fills float64 ``out`` ``(n, width)`` and bool ``valid`` ``(n,)``;
    both are returned in the points' leading shape."""
    flat = np.ascontiguousarray(points, dtype=np.float64).reshape(-1, points.shape[-1])
    out = np.empty((len(flat), width), dtype=np.float64)
    valid = np.empty(len(flat), dtype=np.bool_)
    fill(flat, out, valid)
    return out.reshape(points.shape[:-1] + (width,)), valid.reshape(points.shape[:-1])


def _run_kernel(kern, points: np.ndarray, width: int) -> tuple[np.ndarray, np.ndarray]:
    return run_rows(points, width, lambda flat, out, valid: kern.fn(flat, kern.params, out, valid))


def project_kernel(kern, d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Pixel positions (float64 ``(..., 2)``) and validity (bool ``(...)``) of directions ``d`` (``(..., 3)``,
    any length) through a lens's :class:`~lenslab.lenses.core.protocol.PixelKernel`: zero and non-finite
    directions are invalid, and every invalid position is 0. The kernel releases the GIL, so bands of a warp
    project on several threads."""
    return _run_kernel(kern, d, 2)


def unproject_kernel(kern, xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit directions (float64 ``(..., 3)``) and validity (bool ``(...)``) of pixel positions ``xy``
    (``(..., 2)``, any length) through a lens's :class:`~lenslab.lenses.core.protocol.DirKernel`: non-finite
    pixels have no ray, and every direction without one is 0. The kernel releases the GIL."""
    return _run_kernel(kern, xy, 3)


def _kernel_or_steps(points: np.ndarray, kern, width: int, numpy_steps) -> tuple[np.ndarray, np.ndarray]:
    if kern is not None:  # the same steps, compiled, in one pass
        return _run_kernel(kern, points, width)
    with np.errstate(all="ignore"):
        return numpy_steps(points)


def dir_to_pixel_through(lens, dirs, numpy_steps) -> tuple[np.ndarray, np.ndarray]:
    """A model's ``dir_to_pixel``: its compiled :meth:`~lenslab.lenses.core.base.Lens.pixel_kernel` when it has
    one, else ``numpy_steps`` (the same steps in NumPy) on the float64 directions, floating-point warnings off
    (the steps flag what they could not map as invalid)."""
    d = as_points(dirs, 3, "directions")
    return _kernel_or_steps(d, lens.pixel_kernel(), 2, numpy_steps)


def pixel_to_dir_through(lens, xy, numpy_steps) -> tuple[np.ndarray, np.ndarray]:
    """A model's ``pixel_to_dir``: its compiled :meth:`~lenslab.lenses.core.base.Lens.dir_kernel` when it has one,
    else ``numpy_steps`` on the float64 pixel positions, floating-point warnings off."""
    xy = as_points(xy, 2, "pixel coordinates")
    return _kernel_or_steps(xy, lens.dir_kernel(), 3, numpy_steps)


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
