"""Where the Dask scheduler is (``--scheduler``, ``--scheduler-file``, ``DASK_SCHEDULER_ADDRESS``) and
the client to it. Dask is imported only when a cluster is used."""

from __future__ import annotations

import contextlib
import os
import re
from typing import Iterator

ENV = "DASK_SCHEDULER_ADDRESS"
CONNECT_TIMEOUT = 15.0  # seconds: --scheduler-timeout's default


def scheduler_address(args) -> dict | None:
    """``{"address": ...}`` from ``--scheduler``, from the file ``--scheduler-file`` names, else from
    ``DASK_SCHEDULER_ADDRESS``; None: run on this machine. A value that cannot be an address, or a file
    that is not a scheduler file, is a usage error now (nothing is waited for)."""
    from lenslab.errors import UsageError

    address = getattr(args, "scheduler", None)
    path = getattr(args, "scheduler_file", None)
    if address and path:
        raise UsageError("give --scheduler or --scheduler-file, not both")
    if path:
        return {"address": check_address(read_scheduler_file(path), f"--scheduler-file {path}")}
    if address:
        return {"address": check_address(address, "--scheduler")}
    address = os.environ.get(ENV) or None
    return {"address": check_address(address, ENV)} if address else None


#: what an address looks like: PROTOCOL://HOST:PORT, or HOST:PORT (tcp)
_ADDRESS = re.compile(r"^(?:(tcp|tls|ws|wss|ucx|inproc)://)?(\[[0-9a-fA-F:]+\]|[A-Za-z0-9_.-]+):(\d{1,5})$")
SCHEDULER_FILE_LIMIT = 1 << 20


def check_address(address: str, where: str) -> str:
    """``address`` if it has the form of a scheduler's address, else a usage error naming ``where``."""
    from lenslab.errors import UsageError

    text = str(address).strip()
    m = _ADDRESS.match(text)
    if not m or not 0 < int(m.group(3)) < 65536:
        raise UsageError(f"{where}: {text[:60]!r} is not a scheduler address; give tcp://HOST:PORT "
                         "(e.g. tcp://127.0.0.1:8786)")
    return text if m.group(1) else f"tcp://{text}"


def read_scheduler_file(path: str) -> str:
    """The address in the JSON file ``dask scheduler --scheduler-file FILE`` writes; anything else (no
    such file, not a regular file, too large, not that JSON) is a usage error."""
    import json
    import stat

    from lenslab.errors import UsageError

    try:
        st = os.stat(path)
    except OSError as exc:
        raise UsageError(f"--scheduler-file {path}: {(exc.strerror or 'cannot be read').lower()} (the file "
                         "'dask scheduler --scheduler-file FILE' writes)") from None
    if not stat.S_ISREG(st.st_mode) or st.st_size > SCHEDULER_FILE_LIMIT:
        raise UsageError(f"--scheduler-file {path}: not a scheduler file (a small JSON file written by "
                         "'dask scheduler --scheduler-file FILE')")
    try:
        with open(path, "rb") as f:
            data = json.loads(f.read(SCHEDULER_FILE_LIMIT))
        address = data["address"]
        if not isinstance(address, str):
            raise TypeError
    except (OSError, ValueError, KeyError, TypeError, RecursionError):
        raise UsageError(f"--scheduler-file {path}: not a scheduler file (JSON with the scheduler's "
                         "\"address\", as 'dask scheduler --scheduler-file FILE' writes)") from None
    return address


def open_client(where: dict, timeout: float | None = None):
    """A :class:`distributed.Client` connected to ``where`` (see :func:`scheduler_address`); the caller
    closes it (:func:`close_client`). A scheduler that cannot be reached, or does not answer within
    ``timeout`` seconds (default :data:`CONNECT_TIMEOUT`), is an :class:`OSError` that names it."""
    import threading

    try:
        import dask
        from distributed import Client
    except ImportError:  # pragma: no cover - dask is in the cluster extra
        raise RuntimeError("--scheduler needs Dask: pip install 'lenslab[cluster]'") from None
    target = where.get("address") or where.get("scheduler_file")
    seconds = float(timeout or CONNECT_TIMEOUT)
    quiet_dask_logs()
    made: dict = {}

    def connect():  # in a thread: a scheduler that accepts the connection and never answers cannot hold us
        try:
            with dask.config.set({"distributed.comm.timeouts.connect": f"{seconds}s"}):
                made["client"] = Client(timeout=f"{seconds}s", set_as_default=False, **where)
        except BaseException as exc:  # noqa: BLE001 - reported below, in the caller's thread
            made["error"] = exc

    t = threading.Thread(target=connect, name="lenslab-connect", daemon=True)
    t.start()
    t.join(seconds + 1.0)
    if t.is_alive():
        raise OSError(f"the Dask scheduler at {target} did not answer within {seconds:g} s "
                      "(--scheduler-timeout)")
    exc = made.get("error")
    if exc is not None:
        reason = " ".join(str(exc).split("\n")[0].split())[:200] or type(exc).__name__
        raise OSError(f"cannot reach the Dask scheduler at {target}: {reason}")
    return made["client"]


def quiet_dask_logs() -> None:
    """Dask's own log lines (a reconnect's tracebacks, a lost connection) stay off the terminal: the
    command says what happened in one line of its own."""
    import logging

    for name in ["distributed"] + [n for n in logging.root.manager.loggerDict if n.startswith("distributed.")]:
        logging.getLogger(name).setLevel(logging.CRITICAL + 1)


def close_client(client) -> None:
    with contextlib.suppress(Exception):
        client.close(timeout=5)


@contextlib.contextmanager
def client_for(where: dict, timeout: float | None = None) -> Iterator:
    """A :class:`distributed.Client` connected to ``where`` within ``timeout`` seconds (see
    :func:`open_client`), closed after."""
    client = open_client(where, timeout)
    try:
        yield client
    finally:
        close_client(client)


#: Dask settings for lenslab's workers (docs/guide/batches.md gives them as a config file for ``dask worker``;
#: docs/design.md, "Clusters: scaling", has the measurements).
#:
#: - Dask's nanny starts workers with ``MALLOC_TRIM_THRESHOLD_=65536``, which makes the C library give every
#:   freed image buffer back to the system and fault it in again for the next frame: measured on a 2048x1024
#:   EXR frame into a fisheye, 152 ms a frame with it, 125 ms without (one worker).
#: - A worker samples its running task's stack every 10 ms (its profiler) and measures its event loop every
#:   20 ms, each time taking the GIL from the task: 3.4% of a core per worker, busy or not (a worker's main
#:   thread during a 5 s task), which two workers on two cores take from their tasks. Every 100 ms and 200 ms:
#:   0.8%, and the dashboard's profiles are still drawn.
WORKER_CONFIG = {"distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None,
                 "distributed.worker.profile.interval": "100ms",
                 "distributed.admin.tick.interval": "200ms"}


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
