"""Running a batch on a Dask cluster: one task per file, followed as the tasks complete.

:func:`run_batch` submits one task per (input, output) pair, shows a progress bar over the futures as
they complete, reports each failure with its file and cancels what is left on Ctrl-C. When the batch
ends (done, failed or interrupted) it removes the temporaries that killed workers left beside the
outputs, so every output is complete or absent. :func:`worker_summary` says what each worker did.
"""

from __future__ import annotations

import sys
import time
from typing import Callable, Iterable, Iterator


def on_worker(fn: Callable, *args):
    """Run ``fn(*args)`` on a worker; returns ``(value, worker address, seconds)``."""
    from distributed import get_worker

    start = time.perf_counter()
    value = fn(*args)
    try:
        who = get_worker().address
    except ValueError:  # pragma: no cover - not on a worker (a synchronous test client)
        who = "local"
    return value, who, time.perf_counter() - start


def submit(client, fn: Callable, *args, name: str = "task", **where):
    """Submit ``fn(*args)`` as one task (never cached: a file may change between runs); ``where`` as for
    :meth:`distributed.Client.submit` (``workers=[...]``)."""
    import secrets

    return client.submit(on_worker, fn, *args, pure=False, key=f"lenslab-{name}-{secrets.token_hex(8)}", **where)


def submit_many(client, fn: Callable, jobs: list[tuple], name: str = "task") -> list:
    """Submit ``fn(*job)`` for every job in one message to the scheduler (one task each)."""
    import secrets

    if not jobs:
        return []
    keys = [f"lenslab-{name}-{secrets.token_hex(8)}" for _ in jobs]
    return client.map(on_worker, [fn] * len(jobs), *zip(*jobs), key=keys, pure=False)


def gather_as_completed(client, futures: list, progress: bool = False, unit: str = "file",
                        desc: str | None = None) -> Iterator[tuple]:
    """Yield ``(future, value, worker, seconds, error)`` as the futures complete (``error`` a one-line
    message, or None); a progress bar while they run. Ctrl-C cancels every future not done and re-raises."""
    from distributed import as_completed
    from tqdm import tqdm

    bar = tqdm(total=len(futures), unit=unit, desc=desc, file=sys.stderr, leave=False,
               disable=not (progress and sys.stderr.isatty()))
    try:
        for fut in as_completed(futures, loop=client.loop):
            try:
                value, worker, seconds = fut.result()
                error = None
            except Exception as exc:  # the task raised, or its worker was lost too often (KilledWorker)
                value, worker, seconds = None, "?", 0.0
                error = _one_line(exc)
            bar.update()
            yield fut, value, worker, seconds, error
    except BaseException:  # Ctrl-C or an error of the caller: nothing of this batch keeps running
        client.cancel(futures, force=True)
        raise
    finally:
        bar.close()


def _one_line(exc: BaseException) -> str:
    name = type(exc).__name__
    if name == "KilledWorker":
        return "the workers running it died (the task was tried on several workers)"
    text = str(exc).strip().splitlines()
    return f"{name}: {text[0]}" if text else name


def run_batch(client, task: Callable, jobs: Iterable[tuple], outputs: Iterable, name: str,
              progress: bool = False, workers: dict | None = None) -> list[tuple]:
    """Run ``task(*job)`` for every job on ``client``'s workers, one task each; every task returns
    ``(input, output, error or None, notes)``. Returns those tuples in the jobs' order.

    ``workers`` (a dict) receives per-worker ``[files, seconds]``. Temporaries of ``outputs`` left by
    lost workers are removed at the end, also after Ctrl-C.
    """
    from lenslab.io.atomic import temporaries

    jobs = list(jobs)
    futures = submit_many(client, task, jobs, name=name)
    index = {f.key: i for i, f in enumerate(futures)}
    results: dict[int, tuple] = {}
    try:
        for fut, value, worker, seconds, error in gather_as_completed(client, futures, progress, desc=name):
            i = index[fut.key]
            if error is not None:
                value = (str(jobs[i][0]), str(jobs[i][1]), error, [])
            results[i] = value
            if workers is not None and error is None:
                w = workers.setdefault(worker, [0, 0.0])
                w[0] += 1
                w[1] += seconds
    finally:
        for out in outputs:
            for tmp in temporaries(out):
                tmp.unlink(missing_ok=True)
    return [results[i] for i in range(len(jobs))]


def worker_summary(workers: dict) -> list[str]:
    """One line per worker: its address, the files it did and the time it spent on them."""
    return [f"  {who}: {n} file(s), {seconds:.2f} s" for who, (n, seconds) in sorted(workers.items())]


def skip_existing(pairs: list[tuple], skip: bool) -> tuple[list[tuple], int]:
    """With ``skip``, leave out the pairs whose output exists (a resumed batch); returns (pairs, skipped)."""
    if not skip:
        return pairs, 0
    from pathlib import Path

    left = [p for p in pairs if not Path(p[1]).exists()]
    return left, len(pairs) - len(left)


__all__ = ["run_batch", "gather_as_completed", "submit", "submit_many", "worker_summary", "skip_existing"]
