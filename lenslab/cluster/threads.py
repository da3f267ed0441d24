"""A batch on this machine: several files at once on threads of this process (``--jobs N``).

The heavy parts of a file's work release the GIL (lenslab's compiled kernels, the EXR, TIFF and PNG
codecs), so ``N`` threads warp, convert or tone-map ``N`` files at once while they share what this
process has already loaded: the compiled kernels and a warp's map, made once for the whole batch.
Worker processes would each load the kernels again (about half a second) and make their own map,
which a batch of a few frames cannot win back.

Each file's warnings become its own notes: :func:`recorded_warnings` records the warnings of the
calling thread only while :func:`run_threads` runs (Python's ``catch_warnings`` is one state for the
whole process, so two threads inside it would take each other's warnings).
"""

from __future__ import annotations

import contextlib
import os
import threading
import warnings
from typing import Callable, Iterator, Sequence

_TLS = threading.local()  # .caught: the list the current thread's warnings go to
_HOOKED = threading.Event()  # set while run_threads routes warnings by thread


@contextlib.contextmanager
def recorded_warnings() -> Iterator[list]:
    """The warnings raised in this thread inside the block, as ``warnings.WarningMessage`` items."""
    if not _HOOKED.is_set():
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            yield caught
        return
    caught: list = []
    outer = getattr(_TLS, "caught", None)
    _TLS.caught = caught
    try:
        yield caught
    finally:
        _TLS.caught = outer


_ROUTING = threading.Lock()
_ROUTED = [0, None]  # the blocks inside routed_warnings, and what they replaced (filters, showwarning)


@contextlib.contextmanager
def routed_warnings() -> Iterator[None]:
    """Within the block, each thread's warnings go to its own :func:`recorded_warnings` (each of them, also when
    repeated: a file's notes are its own), those of other threads where they went before. Blocks may run at once
    in several threads (the files of a batch here, the tasks of a many-threaded cluster worker): the first to
    enter routes, the last to leave puts back what was there."""
    from lenslab.errors import NUMPY_NOTES

    with _ROUTING:
        if _ROUTED[0] == 0:
            shown = warnings.showwarning
            _ROUTED[1] = (warnings.filters[:], shown)
            warnings.simplefilter("always")
            warnings.filterwarnings("ignore", message=NUMPY_NOTES, category=RuntimeWarning)

            def route(message, category, filename, lineno, file=None, line=None):
                caught = getattr(_TLS, "caught", None)
                if caught is None:
                    shown(message, category, filename, lineno, file, line)
                else:
                    caught.append(warnings.WarningMessage(message, category, filename, lineno, file, line))

            warnings.showwarning = route
            _HOOKED.set()
        _ROUTED[0] += 1
    try:
        yield
    finally:
        with _ROUTING:
            _ROUTED[0] -= 1
            if _ROUTED[0] == 0:
                _HOOKED.clear()
                warnings.filters[:], warnings.showwarning = _ROUTED[1]
                warnings.simplefilter("default", append=True)  # (a change made so, to refresh Python's cache)
                warnings.filters[:] = _ROUTED[1][0]
                _ROUTED[1] = None


def default_jobs(files: int) -> int:
    """Files at once when the user does not say: one per core, no more than there are files."""
    return max(1, min(len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1,
                      files))


def available_memory() -> int | None:
    """Bytes this process may still take: the system's MemAvailable, or less under a cgroup limit."""
    found = []
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    found.append(int(line.split()[1]) * 1024)
    except (OSError, ValueError, IndexError):
        pass
    try:
        with open("/sys/fs/cgroup/memory.max") as f:
            limit = f.read().strip()
        with open("/sys/fs/cgroup/memory.current") as f:
            used = int(f.read().strip())
        if limit != "max":
            found.append(max(0, int(limit) - used))
    except (OSError, ValueError):
        pass
    return min(found) if found else None


def _peak_rss() -> int:
    import resource

    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024  # Linux reports KiB


def memory_bound(threads: int, per_job: int, available: int | None) -> int:
    """``threads`` capped so that that many jobs of ``per_job`` bytes each use at most 70% of ``available``."""
    if not available or per_job <= 0:
        return threads
    return max(1, min(threads, int(0.7 * available) // per_job))


def run_threads(work: Callable, jobs: Sequence, threads: int, on_done: Callable | None = None,
                first_alone: bool = False, fit_memory: bool = False) -> list:
    """``[work(job) for job in jobs]`` with ``threads`` jobs at once; ``on_done(result)`` is called in this
    thread as each finishes (in the order they finish). Results come back in the jobs' order.

    Each thread runs its job's compiled kernels on ``cores // threads`` threads of its own (at least
    one), and the EXR codec in the calling thread. On Ctrl-C or SIGTERM the jobs not started are dropped
    and the running ones end their file without renaming it (its temporary is removed,
    :data:`lenslab.atomic.STOPPING`), then the interrupt goes on.

    ``first_alone``: the first job runs by itself first, on every core (a warp's first file makes the
    map the others share); with ``fit_memory`` the growth of this process's peak memory during it
    bounds how many of the others run at once (:func:`memory_bound`), so that big files do not exhaust
    the memory (the commands' default; an explicit ``--jobs N`` is taken as it is).
    """
    jobs = list(jobs)
    if first_alone and jobs:
        rss0 = _peak_rss()
        first = work(jobs[0])
        if on_done is not None:
            on_done(first)
        if fit_memory:
            threads = memory_bound(threads, _peak_rss() - rss0, available_memory())
        return [first] + run_threads(work, jobs[1:], threads, on_done)
    threads = max(1, min(int(threads), len(jobs)))
    if threads == 1:
        out = []
        for job in jobs:
            out.append(work(job))
            if on_done is not None:
                on_done(out[-1])
        return out
    import concurrent.futures as cf

    import lenslab.io.exr
    from lenslab.atomic import STOPPING
    from lenslab.warp.kernels.dispatch import default_threads, set_threads

    cores = default_jobs(1 << 30)
    inner = max(1, cores // threads)

    def start() -> None:
        set_threads(min(inner, default_threads()))  # the warp's bands, per thread

    codec_threads = lenslab.io.exr.THREADS
    results: dict[int, object] = {}
    with routed_warnings():
        lenslab.io.exr.THREADS = 0  # the files already fill the cores: no codec pool on top
        pool = cf.ThreadPoolExecutor(threads, initializer=start, thread_name_prefix="lenslab-file")
        try:
            futures = {pool.submit(work, job): i for i, job in enumerate(jobs)}
            for fut in cf.as_completed(futures):
                results[futures[fut]] = fut.result()
                if on_done is not None:
                    on_done(results[futures[fut]])
        except BaseException:  # Ctrl-C, SIGTERM: the files under way are not renamed (their temporaries go)
            STOPPING.set()
            raise
        finally:
            pool.shutdown(wait=True, cancel_futures=True)
            STOPPING.clear()
            lenslab.io.exr.THREADS = codec_threads
    return [results[i] for i in range(len(jobs))]


__all__ = ["recorded_warnings", "routed_warnings", "run_threads", "default_jobs", "memory_bound", "available_memory"]
