"""How the warp's kernels run: one band of output rows per thread, on :func:`threads` threads.

Every compiled kernel releases the GIL (the C++ ones of :mod:`lenslab.warp.kernels.native`, and the numba
ones a :class:`Kernel` wraps), so the engine runs whole bands on a pool of Python threads
(:func:`run_bands`) and keeps every core busy without a parallel build of each kernel.

The thread count is the warp's own: :func:`set_threads` for the calling thread (a batch gives each of its
worker threads a share of the cores), else the environment's ``LENSLAB_THREADS``, else
``NUMBA_NUM_THREADS`` (honoured as before the warp's kernels left numba), else the cores this process may
run on. Asking for it imports nothing: a plain warp never loads numba.

:class:`Kernel` compiles a numba function on its first call, not at import: a module that holds one
(``lenslab.warp.antialias``'s secants of supersampled footprints) costs nothing until that path runs.
"""

from __future__ import annotations

import os
import threading
from concurrent.futures import ThreadPoolExecutor

_local = threading.local()


class Kernel:
    """A function numba compiles on its first call (cached on disk, serially, releasing the GIL);
    ``k(*args)`` runs it."""

    def __init__(self, fn, **options):
        self.fn = fn
        self.options = options
        self.compiled = None
        self.__doc__ = fn.__doc__
        self.__name__ = fn.__name__

    @property
    def serial(self):
        """The compiled dispatcher (numba is imported here, the first time it is needed)."""
        if self.compiled is None:
            import numba

            self.compiled = numba.njit(cache=True, nogil=True, **self.options)(self.fn)
        return self.compiled

    def __call__(self, *args):
        return self.serial(*args)


def kernel(fn) -> Kernel:
    """Decorator: ``fn`` as a :class:`Kernel` (``numba.prange`` loops run as plain loops)."""
    return Kernel(fn)


def _kernel_options(**options):
    """``@kernel.options(fastmath=True)``: a :class:`Kernel` with extra numba options."""
    return lambda fn: Kernel(fn, **options)


kernel.options = _kernel_options


def default_threads() -> int:
    """The process's thread count: ``LENSLAB_THREADS``, else ``NUMBA_NUM_THREADS``, else the cores this
    process may run on (a value that is not a positive whole number is passed over)."""
    for name in ("LENSLAB_THREADS", "NUMBA_NUM_THREADS"):
        try:
            n = int(os.environ.get(name, ""))
        except ValueError:
            continue
        if n >= 1:
            return n
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):  # not on Linux
        return max(1, os.cpu_count() or 1)


def threads() -> int:
    """Threads to run bands on: this thread's :func:`set_threads`, else :func:`default_threads`."""
    n = getattr(_local, "threads", None)
    return n if n is not None else default_threads()


def set_threads(n: int | None) -> None:
    """Run the warps this thread starts on ``n`` threads (None: back to :func:`default_threads`). Like
    numba's ``set_num_threads`` it holds for the calling thread only, so each worker of a batch can take its
    share of the cores. (numba's own count does not matter: its kernels here run serially, one per band.)"""
    _local.threads = None if n is None else max(1, int(n))


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


#: scratch buffers kept between bands and warps (at most this many), so that a band's working arrays (the map
#: lattice's coefficients, the directions it leaves to project) reuse pages already faulted in: fresh pages
#: cost about 1 us each here, 2-3 ms of a 1024x1024 one-shot warp's map
SCRATCH_KEPT = 8
_scratch: list = []
_scratch_lock = threading.Lock()


class scratch:
    """``with scratch(shape, dtype) as a:`` an uninitialised array, from a buffer kept for reuse when one is
    large enough (given back on leaving the block; a caller must not keep the array)."""

    def __init__(self, shape, dtype=float):
        import numpy as np

        self.dtype = np.dtype(dtype)
        self.shape = tuple(int(v) for v in shape)
        self.nbytes = int(np.prod(self.shape)) * self.dtype.itemsize
        self.buf = None

    def __enter__(self):
        import numpy as np

        with _scratch_lock:
            fits = [i for i, b in enumerate(_scratch) if b.nbytes >= self.nbytes]
            if fits:  # the smallest that fits (lists of arrays are searched by position: == compares values)
                self.buf = _scratch.pop(min(fits, key=lambda i: _scratch[i].nbytes))
        if self.buf is None:
            self.buf = np.empty(max(self.nbytes, 1), np.uint8)
        return self.buf[:self.nbytes].view(self.dtype).reshape(self.shape)

    def __exit__(self, *exc):
        with _scratch_lock:
            _scratch.append(self.buf)
            if len(_scratch) > SCRATCH_KEPT:
                _scratch.pop(min(range(len(_scratch)), key=lambda i: _scratch[i].nbytes))
        self.buf = None
