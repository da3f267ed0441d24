"""Compiled kernels: one serial build each, run in parallel band by band.

Each kernel is compiled once (numba, cached on disk), serially and without the GIL, so the engine
runs one band per thread (:func:`run_bands`). A parallel build per kernel would double what a first
run has to compile, and starting numba's worker threads for each small call costs up to a scheduler
time slice on a busy machine; whole bands per thread keep every core busy with neither cost.
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import numba


class Kernel:
    """A function compiled once, serially and releasing the GIL; ``k(*args)`` runs it."""

    def __init__(self, fn, **options):
        self.serial = numba.njit(cache=True, nogil=True, **options)(fn)
        self.__doc__ = fn.__doc__
        self.__name__ = fn.__name__

    def __call__(self, *args):
        return self.serial(*args)


def kernel(fn) -> Kernel:
    """Decorator: compile ``fn`` (``numba.prange`` loops run as plain loops) as a :class:`Kernel`."""
    return Kernel(fn)


def _kernel_options(**options):
    """``@kernel.options(fastmath=True)``: a :class:`Kernel` with extra numba options."""
    return lambda fn: Kernel(fn, **options)


kernel.options = _kernel_options


def threads() -> int:
    """Threads to run bands on: numba's thread count (``NUMBA_NUM_THREADS``, ``numba.set_num_threads``)."""
    return max(1, int(numba.get_num_threads()))


def run_bands(jobs, work, on_done=None) -> list:
    """``[work(job) for job in jobs]``, on :func:`threads` threads when there is more than one job
    (results in order); ``on_done(result)`` is called in the calling thread as each finishes, in order."""
    jobs = list(jobs)
    n = min(threads(), len(jobs))
    if n <= 1:
        out = []
        for job in jobs:
            res = work(job)
            if on_done is not None:
                on_done(res)
            out.append(res)
        return out
    with ThreadPoolExecutor(max_workers=n) as pool:
        futures = [pool.submit(work, job) for job in jobs]
        out = []
        for fut in futures:
            res = fut.result()
            if on_done is not None:
                on_done(res)
            out.append(res)
        return out
