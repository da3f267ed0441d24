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

import math
import os
import threading

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
    (results in order); ``on_done(result)`` is called in the calling thread as each finishes, in order.

    The calling thread takes jobs too, beside ``threads() - 1`` helpers of a pool kept for the process (a warp
    runs several of these a call: starting threads for each waited on the scheduler, a few milliseconds a
    start on a loaded machine). Jobs are taken one at a time, so uneven jobs balance themselves. A job that
    calls ``run_bands`` itself runs its jobs in its own thread (the cores are already busy). The first error
    stops the jobs not yet started and is raised once those started have finished."""
    jobs = list(jobs)
    n = 1 if getattr(_local, "in_job", False) else min(threads(), len(jobs))
    if n <= 1:
        out = []
        for job in jobs:
            res = work(job)
            if on_done is not None:
                on_done(res)
            out.append(res)
        return out
    run = _Run(jobs, work)
    _pool.submit(run.take, n - 1)
    flushed = 0
    try:
        while True:
            took = run.take_one()
            with run.cond:
                while not took and run.error is None and not run.finished[flushed]:
                    run.cond.wait()  # nothing left to take: wait for the helpers' jobs
                ready = flushed
                while ready < len(jobs) and run.finished[ready]:
                    ready += 1
                error = run.error
            if error is not None:
                break
            if on_done is not None:
                for i in range(flushed, ready):
                    on_done(run.results[i])
            flushed = ready
            if flushed == len(jobs):
                return run.results
        raise error
    except BaseException:
        with run.cond:  # no job starts now; those under way finish first (they write into the caller's arrays)
            run.stop = True
            while run.running:
                run.cond.wait()
        raise


class _Run:
    """The jobs of one :func:`run_bands` call, taken one at a time by the caller and the pool's helpers."""

    def __init__(self, jobs, work):
        self.jobs, self.work = jobs, work
        self.results = [None] * len(jobs)
        self.finished = [False] * len(jobs)
        self.started = 0
        self.running = 0
        self.error = None
        self.stop = False
        self.cond = threading.Condition()

    def take_one(self) -> bool:
        """Run the next job not yet taken in this thread; False when none is left."""
        with self.cond:
            if self.stop or self.error is not None or self.started >= len(self.jobs):
                return False
            i = self.started
            self.started += 1
            self.running += 1
        outer = getattr(_local, "in_job", False)
        _local.in_job = True
        try:
            res, err = self.work(self.jobs[i]), None
        except BaseException as exc:  # handed to the caller
            res, err = None, exc
        finally:
            _local.in_job = outer
        with self.cond:
            self.results[i] = res
            self.finished[i] = True
            self.running -= 1
            if err is not None and self.error is None:
                self.error = err
            self.cond.notify_all()
        return True

    def take(self) -> None:
        while self.take_one():
            pass


class _Pool:
    """Helper threads kept for the process (daemons, idle on a queue between runs; started as needed, none
    before the first run with more than one thread; a forked child starts its own)."""

    def __init__(self):
        import queue

        self.queue = queue.SimpleQueue()
        self.size = 0
        self.lock = threading.Lock()

    def submit(self, fn, count: int) -> None:
        with self.lock:
            while self.size < count:
                threading.Thread(target=self._serve, name=f"lenslab-band-{self.size}", daemon=True).start()
                self.size += 1
        for _ in range(count):
            self.queue.put(fn)

    def _serve(self) -> None:
        while True:
            fn = self.queue.get()
            try:
                fn()
            except BaseException:  # pragma: no cover - _Run.take hands every error to its caller
                pass
            del fn  # (idle, a helper keeps nothing of its last run: the source and output arrays its bands drew)


_pool = _Pool()


def _reset_pool() -> None:
    global _pool
    _pool = _Pool()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_reset_pool)


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
        self.nbytes = math.prod(self.shape) * self.dtype.itemsize
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


class contiguous_rows:
    """``with contiguous_rows(out, alpha) as (o, a):`` C-contiguous arrays for a sampler to draw a band into:
    ``out`` and ``alpha`` themselves, or for either that is not (a band of a strided output: the colour and alpha of
    one RGBA image) a :class:`scratch` copy, written back when the block ends without an error; a plane whose rows
    are all one row (a coverage nobody keeps, :func:`lenslab.warp.checks.drawn_into`) is drawn in scratch and not
    written back. ``drawn_over``: the sampler writes every pixel of the rows, so the scratch arrays are not given
    the rows' values first."""

    def __init__(self, out, alpha, drawn_over: bool = False):
        self.given, self.copies, self.drawn_over = (out, alpha), None, drawn_over

    def __enter__(self):
        import numpy as np

        if all(a.flags.c_contiguous for a in self.given):
            return self.given
        self.copies = [None if a.flags.c_contiguous else scratch(a.shape, np.float32) for a in self.given]
        self.drawn = tuple(a if c is None else c.__enter__() for a, c in zip(self.given, self.copies))
        if not self.drawn_over:
            for a, d, c in zip(self.given, self.drawn, self.copies):
                if c is not None:
                    d[...] = a  # (what the sampler leaves undrawn stays as it was)
        return self.drawn

    def __exit__(self, kind, *exc):
        if self.copies is None:
            return
        for a, d, c in zip(self.given, self.drawn, self.copies):
            if c is None:
                continue
            if kind is None and (a.strides[0] != 0 or a.shape[0] < 2):
                a[...] = d
            c.__exit__(kind, *exc)
        self.copies = self.drawn = None
