"""Compiled kernels in two builds, parallel and serial, chosen per call by the amount of work.

Starting numba's worker threads costs little on an idle machine but up to a scheduler time slice
(milliseconds) on a busy one, which dominates small calls (a narrow band, a thumbnail). Kernels
decorated with :func:`kernel` run serially below ``PARALLEL_MIN_WORK`` work items, or when numba is
limited to one thread, and in parallel otherwise.
"""

from __future__ import annotations

import numba

PARALLEL_MIN_WORK = 1 << 16  # output samples (or similar units) below which a call runs serially


class Kernel:
    """A function compiled twice: ``k(*args, work=n)`` picks the build."""

    def __init__(self, fn, **options):
        self.parallel = numba.njit(parallel=True, cache=True, **options)(fn)
        # a distinct function object, so that the two builds keep distinct on-disk caches
        clone = type(fn)(fn.__code__, fn.__globals__, fn.__name__ + "_serial", fn.__defaults__, fn.__closure__)
        clone.__qualname__ = fn.__qualname__ + "_serial"
        self.serial = numba.njit(parallel=False, cache=True, **options)(clone)
        self.__doc__ = fn.__doc__
        self.__name__ = fn.__name__

    def __call__(self, *args, work: int):
        if work >= PARALLEL_MIN_WORK and numba.get_num_threads() > 1:
            return self.parallel(*args)
        return self.serial(*args)


def kernel(fn) -> Kernel:
    """Decorator: compile ``fn`` (which may use ``numba.prange``) as a :class:`Kernel`."""
    return Kernel(fn)


def _kernel_options(**options):
    """``@kernel.options(fastmath=True)``: a :class:`Kernel` with extra numba options."""
    return lambda fn: Kernel(fn, **options)


kernel.options = _kernel_options
