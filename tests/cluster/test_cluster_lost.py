"""A scheduler lost in the middle of a batch: one line, a correct count, and no output written afterwards.

The scheduler and its worker are processes of their own (``dask scheduler``, ``dask worker``), so the
test can kill the scheduler outright. The worker is frozen (SIGSTOP) first, so the batch cannot end
before the scheduler is gone; every wait is for a state, never a duration.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("distributed")

from lenslab.io import write  # noqa: E402

pytestmark = pytest.mark.slow
GUARD = 300  # seconds, against a hang only


def _wait(condition, what: str) -> None:
    deadline = time.monotonic() + GUARD
    while not condition():
        assert time.monotonic() < deadline, f"hang guard: {what}"
        time.sleep(0.02)


@pytest.fixture()
def cluster(tmp_path):
    """(scheduler process, worker process, scheduler file) of a cluster of one single-threaded worker."""
    from distributed import Client

    sfile = tmp_path / "scheduler.json"
    scheduler = subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_scheduler", "--host", "127.0.0.1",
                                  "--port", "0", "--no-dashboard", "--scheduler-file", str(sfile)],
                                 stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    worker = None
    try:
        _wait(lambda: sfile.is_file() and sfile.stat().st_size > 0, "the scheduler file")
        worker = subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_worker", "--scheduler-file",
                                   str(sfile), "--nthreads", "1", "--no-dashboard", "--no-nanny"],
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        with Client(scheduler_file=str(sfile), set_as_default=False, timeout="60s") as client:
            client.wait_for_workers(1, timeout=GUARD)
        yield scheduler, worker, sfile
    finally:
        for proc in (worker, scheduler):
            if proc is not None and proc.poll() is None:
                with_cont = proc is worker
                if with_cont:
                    os.kill(proc.pid, signal.SIGCONT)
                proc.kill()
                proc.wait()


def test_a_lost_scheduler_is_one_line_with_the_count_of_outputs_done(tmp_path, cluster):
    scheduler, worker, sfile = cluster
    folder = tmp_path / "in"
    folder.mkdir()
    rng = np.random.default_rng(2)
    for i in range(30):
        write(folder / f"f{i:02d}.exr", rng.random((128, 256, 3), dtype=np.float32))
    out = tmp_path / "out"
    proc = subprocess.Popen([sys.executable, "-m", "lenslab", "warp", str(folder), "-o", str(out), "--to",
                             "fisheye:fov=180", "--size", "256x256", "--samples", "4", "-q",
                             "--scheduler-file", str(sfile)], stderr=subprocess.PIPE, text=True)
    try:
        _wait(lambda: out.is_dir() and any(not p.name.startswith(".") for p in out.iterdir())
              or proc.poll() is not None, "a first output")
        os.kill(worker.pid, signal.SIGSTOP)  # the batch cannot end now
        assert proc.poll() is None, proc.stderr.read()
        scheduler.kill()
        scheduler.wait()
        _, err = proc.communicate(timeout=GUARD)
        done = {p.name for p in out.iterdir() if not p.name.startswith(".")}
        os.kill(worker.pid, signal.SIGCONT)  # its task goes on without a scheduler
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 1, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    assert "lost the Dask scheduler" in lines[0] and f"{len(done)} of 30 output(s) are done" in lines[0], err
    worker.kill()
    worker.wait()  # whatever its last task did, it did before this point
    assert {p.name for p in out.iterdir() if not p.name.startswith(".")} == done  # nothing written after
