"""A worker's share of the machine: each task uses the threads its worker was given (a Dask nanny sets
``OMP_NUM_THREADS``), so workers sharing a machine do not fight over its cores. What a task runs is a job
(:func:`lenslab.jobs.runner.execute_staged`)."""

from __future__ import annotations

import os


def worker_threads() -> int | None:
    """The worker's thread allowance (``OMP_NUM_THREADS``, set by the Dask nanny), else None (every core)."""
    try:
        return max(1, int(os.environ.get("OMP_NUM_THREADS", "")))
    except ValueError:
        return None


def limit_threads(n: int | None = None) -> None:
    """OpenCV, the warp's bands and the EXR codec use ``n`` threads (default: the worker's thread allowance)."""
    n = worker_threads() if n is None else n
    if n is None:
        return
    import cv2

    import lenslab.io.exr
    from lenslab.warp.kernels.dispatch import set_threads

    cv2.setNumThreads(n)
    set_threads(n)
    lenslab.io.exr.THREADS = 0 if n == 1 else n  # 0: the codec works in the calling thread, no pool


__all__ = ["worker_threads", "limit_threads"]
