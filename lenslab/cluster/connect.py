"""Where the Dask scheduler is (``--scheduler``, ``--scheduler-file``, ``DASK_SCHEDULER_ADDRESS``) and
the client to it. Dask is imported only when a cluster is used."""

from __future__ import annotations

import contextlib
import os
from typing import Iterator

ENV = "DASK_SCHEDULER_ADDRESS"
CONNECT_TIMEOUT = "10s"


def scheduler_address(args) -> dict | None:
    """``{"address": ...}`` or ``{"scheduler_file": ...}`` from the options, else from
    ``DASK_SCHEDULER_ADDRESS``; None: run on this machine."""
    address = getattr(args, "scheduler", None)
    path = getattr(args, "scheduler_file", None)
    if address and path:
        from lenslab.cli.policy import UsageError

        raise UsageError("give --scheduler or --scheduler-file, not both")
    if path:
        if not os.path.isfile(path):
            raise FileNotFoundError(f"{path}: no such scheduler file (written by 'dask scheduler "
                                    "--scheduler-file FILE')")
        return {"scheduler_file": str(path)}
    address = address or os.environ.get(ENV) or None
    return {"address": address} if address else None


def open_client(where: dict):
    """A :class:`distributed.Client` connected to ``where`` (see :func:`scheduler_address`); the caller
    closes it (:func:`close_client`). A scheduler that cannot be reached within ``CONNECT_TIMEOUT`` is an
    :class:`OSError` that names it."""
    try:
        from distributed import Client
    except ImportError:  # pragma: no cover - dask is in the cluster extra
        raise RuntimeError("--scheduler needs Dask: pip install 'lenslab[cluster]'") from None
    target = where.get("address") or where.get("scheduler_file")
    try:
        return Client(timeout=CONNECT_TIMEOUT, set_as_default=False, **where)
    except (OSError, TimeoutError) as exc:
        reason = " ".join(str(exc).split()) or type(exc).__name__
        raise OSError(f"cannot reach the Dask scheduler at {target}: {reason}") from None


def close_client(client) -> None:
    with contextlib.suppress(Exception):
        client.close(timeout=5)


@contextlib.contextmanager
def client_for(where: dict) -> Iterator:
    """A :class:`distributed.Client` connected to ``where`` (see :func:`open_client`), closed after."""
    client = open_client(where)
    try:
        yield client
    finally:
        close_client(client)


#: Dask settings for lenslab's workers (README, "Beyond one machine", gives them as a config file for
#: ``dask worker``). Dask's nanny starts workers with ``MALLOC_TRIM_THRESHOLD_=65536``, which makes the C
#: library give every freed image buffer back to the system and fault it in again for the next frame:
#: measured on a 2048x1024 EXR frame into a fisheye, 152 ms a frame with it, 125 ms without (one worker).
WORKER_CONFIG = {"distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None}


@contextlib.contextmanager
def local_cluster(workers: int = 2, threads: int = 1) -> Iterator:
    """A scheduler and ``workers`` worker processes on this machine (no dashboard), with a client to it."""
    import warnings

    from distributed import Client, LocalCluster

    import dask

    with warnings.catch_warnings(), dask.config.set(WORKER_CONFIG):
        # the scheduler's status page moves to a free port: nothing to report
        warnings.filterwarnings("ignore", message="Port .* is already in use")
        cluster = LocalCluster(n_workers=workers, threads_per_worker=threads, processes=True,
                               dashboard_address=None, silence_logs=40)
    with cluster, Client(cluster, set_as_default=False) as client:
        yield client


__all__ = ["scheduler_address", "open_client", "close_client", "client_for", "local_cluster", "ENV", "WORKER_CONFIG"]
