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


def default_jobs(files: int) -> int:
    """Files at once when the user does not say: one per core, no more than there are files."""
    return max(1, min(len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1,
                      files))


def run_threads(work: Callable, jobs: Sequence, threads: int, on_done: Callable | None = None) -> list:
    """``[work(job) for job in jobs]`` with ``threads`` jobs at once; ``on_done(result)`` is called in this
    thread as each finishes (in the order they finish). Results come back in the jobs' order.

    Each thread runs its job's compiled kernels on ``cores // threads`` threads of its own (at least
    one), and the EXR codec in the calling thread. On Ctrl-C the jobs not started are dropped and the
    running ones finish their file (each output is written to a temporary name and renamed), then the
    interrupt goes on.
    """
    import concurrent.futures as cf

    jobs = list(jobs)
    threads = max(1, min(int(threads), len(jobs)))
    if threads == 1:
        out = []
        for job in jobs:
            out.append(work(job))
            if on_done is not None:
                on_done(out[-1])
        return out
    import numba

    import lenslab.io.exr
    from lenslab.cli.policy import _NUMPY_NOTES

    cores = default_jobs(1 << 30)
    inner = max(1, cores // threads)

    def start() -> None:
        numba.set_num_threads(min(inner, numba.config.NUMBA_NUM_THREADS))  # per thread in numba

    codec_threads = lenslab.io.exr.THREADS
    results: dict[int, object] = {}
    with warnings.catch_warnings():
        warnings.simplefilter("always")  # each file's repeated warnings are its own notes
        warnings.filterwarnings("ignore", message=_NUMPY_NOTES, category=RuntimeWarning)
        shown = warnings.showwarning

        def route(message, category, filename, lineno, file=None, line=None):
            caught = getattr(_TLS, "caught", None)
            if caught is None:
                shown(message, category, filename, lineno, file, line)
            else:
                caught.append(warnings.WarningMessage(message, category, filename, lineno, file, line))

        warnings.showwarning = route
        _HOOKED.set()
        lenslab.io.exr.THREADS = 0  # the files already fill the cores: no codec pool on top
        pool = cf.ThreadPoolExecutor(threads, initializer=start, thread_name_prefix="lenslab-file")
        try:
            futures = {pool.submit(work, job): i for i, job in enumerate(jobs)}
            for fut in cf.as_completed(futures):
                results[futures[fut]] = fut.result()
                if on_done is not None:
                    on_done(results[futures[fut]])
        finally:
            pool.shutdown(wait=True, cancel_futures=True)
            _HOOKED.clear()
            lenslab.io.exr.THREADS = codec_threads
    return [results[i] for i in range(len(jobs))]


__all__ = ["recorded_warnings", "run_threads", "default_jobs"]
