"""Running tasks on a Dask cluster: submitted in one message, followed as they complete.

:func:`submit_many` sends one task per job; :func:`gather_as_completed` shows a progress bar over the
futures as they complete, reports each failure in one line, cancels what is left on Ctrl-C and turns a
lost scheduler into one :class:`SchedulerLost`. :func:`worker_summary` says what each worker did.
What the tasks are is the caller's business (:mod:`lenslab.jobs.runner`).
"""

from __future__ import annotations

import sys
import time
from typing import Callable, Iterator


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


class SchedulerLost(ConnectionError):
    """The connection to the scheduler went away during a batch: the tasks not reported are lost."""

    def __init__(self, address: str):
        super().__init__(f"lost the Dask scheduler at {address}")
        self.address = address
        self.done = 0
        self.total = 0


def _lost(client, exc: BaseException) -> bool:
    """Whether a task's error says the scheduler went away (its future cancelled under the client)."""
    return type(exc).__name__ in ("FutureCancelledError", "CancelledError", "CommClosedError") or \
        getattr(client, "status", "running") not in ("running", "newly-created")


def gather_as_completed(client, futures: list, progress: bool = False, unit: str = "file",
                        desc: str | None = None) -> Iterator[tuple]:
    """Yield ``(future, value, worker, seconds, error)`` as the futures complete (``error`` a one-line
    message, or None); a progress bar while they run. Ctrl-C cancels every future not done and re-raises;
    a lost scheduler raises :class:`SchedulerLost` (one error, not one per task)."""
    from distributed import as_completed
    from tqdm import tqdm

    from lenslab.errors import stop_signal

    bar = tqdm(total=len(futures), unit=unit, desc=desc, file=sys.stderr, leave=False,
               disable=not (progress and sys.stderr.isatty()))
    address = getattr(getattr(client, "scheduler", None), "address", "?")
    try:
        for fut in as_completed(futures, loop=client.loop):
            try:
                value, worker, seconds = fut.result()
                error = None
            except BaseException as exc:  # the task raised, or its worker was lost too often (KilledWorker)
                if stop_signal(exc) is not None:  # Ctrl-C, also as the RuntimeError of an interrupted wait
                    raise
                if _lost(client, exc):
                    raise SchedulerLost(address) from None
                value, worker, seconds = None, "?", 0.0
                error = _one_line(exc)
            bar.update()
            yield fut, value, worker, seconds, error
    except BaseException:  # Ctrl-C or an error of the caller: nothing of this batch keeps running
        _cancel(client, futures)
        raise
    finally:
        bar.close()


def _cancel(client, futures) -> None:
    """Cancel ``futures`` without waiting more than a few seconds for a scheduler that may be gone."""
    import threading

    def cancel():
        try:
            client.cancel(futures, force=True)
        except Exception:  # noqa: BLE001 - no scheduler: nothing of this batch runs on it any more
            pass

    t = threading.Thread(target=cancel, daemon=True)
    t.start()
    t.join(5.0)


def _one_line(exc: BaseException) -> str:
    name = type(exc).__name__
    if name == "KilledWorker":
        return "the workers running it died (the task was tried on several workers)"
    text = str(exc).strip().splitlines()
    return f"{name}: {text[0]}" if text else name


def worker_summary(workers: dict) -> list[str]:
    """One line per worker: its address, the files it did and the time it spent on them."""
    return [f"  {who}: {n} file(s), {seconds:.2f} s" for who, (n, seconds) in sorted(workers.items())]


__all__ = ["gather_as_completed", "submit", "submit_many", "worker_summary", "SchedulerLost"]
