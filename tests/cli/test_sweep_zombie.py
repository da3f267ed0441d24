"""A temporary left by a killed writer that its parent has not waited for yet (a zombie: what a container's first
process leaves when it reaps no child) is swept as any dead writer's is: the zombie runs no more. Its state is the
one ``ps`` (procps) reports, ``Z``."""

from __future__ import annotations

import shutil
import signal
import subprocess
import sys
import time

import pytest

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux") or shutil.which("ps") is None,
                                reason="zombies are read from Linux's /proc; ps names their state")

HANG_GUARD = 60.0  # seconds: only a hung machine takes this long for a process to end


def _state(pid: int) -> str:
    return subprocess.run(["ps", "-o", "stat=", "-p", str(pid)], capture_output=True, text=True).stdout.strip()


def test_a_temporary_of_a_zombie_writer_is_swept(tmp_path):
    from lenslab.atomic import HOST
    from lenslab.staging import owner_alive, sweep

    child = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(600)"])
    try:
        child.send_signal(signal.SIGKILL)  # killed, not waited for: a zombie until reaped
        deadline = time.monotonic() + HANG_GUARD
        while not _state(child.pid).startswith("Z"):
            assert time.monotonic() < deadline, _state(child.pid)
            time.sleep(0.01)
        out = tmp_path / "out"
        out.mkdir()
        left = out / f".frame000.tmp-{child.pid}-{HOST}-0123abcd.exr"
        left.write_bytes(b"left by a killed writer")
        assert not owner_alive(child.pid)
        assert sweep([out]) == [left]
        assert not left.exists()
    finally:
        child.kill()
        child.wait(timeout=HANG_GUARD)


def test_a_running_writer_is_alive(tmp_path):
    from lenslab.staging import owner_alive

    child = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(600)"])
    try:
        assert _state(child.pid)[:1] in ("S", "R", "D")
        assert owner_alive(child.pid)
    finally:
        child.kill()
        child.wait(timeout=HANG_GUARD)
