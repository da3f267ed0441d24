"""Process-wide settings for a ``tracer render``, made before NumPy loads.

A render runs its bands on its own threads and allocates the same large arrays band after band; two
defaults of the process work against that, each measured on a 256x256 64 spp render of the Cornell box:

- **BLAS threads.** The camera turns its ray directions with a 3x3 matrix product per band; OpenBLAS ran it on
  threads of its own that competed with the bands for the cores (about 10% of the CPU time, for the same image).
  One BLAS thread, unless the user has chosen.
- **Memory returned and faulted in again.** glibc's malloc serves arrays above its mmap threshold with fresh
  pages and gives them back when they are freed, so every band faulted its megabytes of scratch in again:
  0.2-0.5 s of system time per render against 0.07-0.1 s when freed memory stays with the process (glibc's
  ``mallopt``: no mmap below 32 MiB, its largest threshold, and no trimming below 2 GiB; a render's peak is
  bounded by its batch size, so this keeps at most that peak). Skipped where the C library has no ``mallopt`` (macOS, Windows) or the
  user has set ``MALLOC_MMAP_THRESHOLD_`` or ``MALLOC_TRIM_THRESHOLD_``.
- **Cycle collection** during the imports (a render's own arrays make no cycles): off from the start, as
  :func:`tracer.cli.run_render` keeps it during the render (it turns it back on when done).

A Dask worker tracing tiles (:mod:`tracer.tiles`) is started by the nanny, already with NumPy loaded: it
keeps freed memory from its first tile on (:func:`prepare_worker`).
"""

from __future__ import annotations

import ctypes
import gc
import os

M_TRIM_THRESHOLD, M_MMAP_THRESHOLD = -1, -3  # glibc's malloc.h
MMAP_THRESHOLD = 32 << 20  # glibc's largest on 64-bit systems (larger values are refused)
TRIM_THRESHOLD = 2**31 - 1


def prepare_render() -> None:
    """BLAS on one thread, freed memory kept, no cycle collection (see the module's note); call before NumPy
    is imported."""
    gc.disable()
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    if any(k in os.environ for k in ("MALLOC_MMAP_THRESHOLD_", "MALLOC_TRIM_THRESHOLD_")):
        return
    keep_freed_memory()


def keep_freed_memory() -> bool:
    """glibc's malloc serves allocations below 32 MiB from its heaps and keeps what is freed there (see the
    module's note); takes effect for every later allocation of this process. False where the C library has
    no ``mallopt``."""
    try:
        libc = ctypes.CDLL(None)
        mallopt = libc.mallopt
    except (OSError, AttributeError, TypeError):  # no C library to open by name (Windows), or no mallopt
        return False
    mallopt.argtypes, mallopt.restype = [ctypes.c_int, ctypes.c_int], ctypes.c_int
    return bool(mallopt(M_MMAP_THRESHOLD, MMAP_THRESHOLD)) and bool(mallopt(M_TRIM_THRESHOLD, TRIM_THRESHOLD))


_WORKER_PREPARED: list[bool] = []


def prepare_worker() -> None:
    """The same memory setting in a Dask worker's process, once, before its first tile.

    A worker is started by Dask's nanny, not by ``tracer render``, so :func:`prepare_render` never ran
    there: every band of every tile faulted its scratch in again, and with two workers on two cores the
    page faults of one slowed the other's (docs/design.md, "Clusters: scaling"). The nanny sets
    ``MALLOC_TRIM_THRESHOLD_`` for every worker it starts, so unlike a render's own process the variable
    says nothing of the user's wish and the setting is made whatever it holds. BLAS is on the worker's
    threads already (the nanny sets ``OPENBLAS_NUM_THREADS`` before NumPy loads).
    """
    if not _WORKER_PREPARED:
        _WORKER_PREPARED.append(keep_freed_memory())
