"""SIGTERM, SIGHUP and Ctrl-C end a batch the same way, and a batch killed outright is resumed cleanly.

Every wait below is for a state (an output on disk, a temporary on disk, a process stopped by SIGSTOP),
never for a duration: a stopped process cannot finish its batch between the check and the signal.
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

from tests.child_signals import default_stop_signals

from lenslab.io import read, write

pytestmark = pytest.mark.slow

HANG_GUARD = 300  # seconds: only against a test that would otherwise wait forever on a broken build


def _frames(folder: Path, n: int, size=(256, 128)) -> list[Path]:
    folder.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(1)
    paths = []
    for i in range(n):
        paths.append(folder / f"frame{i:03d}.exr")
        write(paths[-1], (rng.random((size[1], size[0], 3), dtype=np.float32) * 4).astype(np.float32))
    return paths


def _outputs(folder: Path) -> set[str]:
    return {p.name for p in folder.iterdir() if not p.name.startswith(".")} if folder.is_dir() else set()


def _temporaries(folder: Path) -> list[str]:
    return [p.name for p in folder.iterdir() if ".tmp-" in p.name] if folder.is_dir() else []


def _warp(tmp_path: Path, *extra: str) -> list[str]:
    return [sys.executable, "-m", "lenslab", "warp", str(tmp_path / "in"), "-o", str(tmp_path / "out"),
            "--to", "fisheye:fov=180", "--size", "384x384", "--samples", "4", "--pixel-type", "float", *extra]


def _wait_for(condition, proc) -> None:
    deadline = time.monotonic() + HANG_GUARD
    while not condition():
        assert proc.poll() is None, "the batch ended before the state was reached"
        assert time.monotonic() < deadline, "hang guard"
        time.sleep(0.001)


@pytest.mark.parametrize("sig,code,name", [(signal.SIGTERM, 143, "SIGTERM"), (signal.SIGHUP, 129, "SIGHUP"),
                                           (signal.SIGINT, 130, "Ctrl-C")])
@pytest.mark.parametrize("jobs", ["1", "2"])
def test_a_stop_signal_mid_batch_ends_it_like_ctrl_c(tmp_path, sig, code, name, jobs):
    frames = _frames(tmp_path / "in", 24)
    out = tmp_path / "out"
    proc = subprocess.Popen(_warp(tmp_path, "--jobs", jobs), stderr=subprocess.PIPE, text=True,
                            preexec_fn=default_stop_signals)
    try:
        _wait_for(lambda: len(_outputs(out)) >= 1, proc)  # the batch is under way
        proc.send_signal(signal.SIGSTOP)  # frozen: it cannot finish before the signal
        assert proc.poll() is None
        proc.send_signal(sig)
        proc.send_signal(signal.SIGCONT)
        _, err = proc.communicate(timeout=HANG_GUARD)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == code, err
    assert err.strip().splitlines()[-1] == f"lenslab warp: interrupted ({name}); unfinished outputs removed", err
    assert "Traceback" not in err
    assert _temporaries(out) == []
    written = _outputs(out)
    assert 1 <= len(written) < len(frames)
    for name_ in written:  # whatever was written is whole
        image, _ = read(out / name_)
        assert image.shape == (384, 384, 4)


def test_a_batch_killed_outright_is_resumed_without_its_temporaries(tmp_path):
    frames = _frames(tmp_path / "in", 24)
    out = tmp_path / "out"
    proc = subprocess.Popen(_warp(tmp_path, "--jobs", "1", "-q"), stderr=subprocess.PIPE, text=True,
                            preexec_fn=default_stop_signals)
    try:
        while True:  # stop the process while it writes an output (a temporary is on disk)
            _wait_for(lambda: _temporaries(out), proc)
            proc.send_signal(signal.SIGSTOP)
            if _temporaries(out):
                break
            proc.send_signal(signal.SIGCONT)  # it renamed that one meanwhile: catch the next
        proc.send_signal(signal.SIGKILL)
        proc.wait(timeout=HANG_GUARD)  # reaped: its pid no longer runs
    finally:
        if proc.poll() is None:
            proc.kill()
    left = _temporaries(out)
    assert left and all(f"-{proc.pid}-" in name for name in left)  # named for the dead process
    resumed = subprocess.run(_warp(tmp_path, "--skip-existing"), capture_output=True, text=True,
                             timeout=HANG_GUARD)
    assert resumed.returncode == 0, resumed.stderr
    assert _temporaries(out) == []
    assert _outputs(out) == {f.stem + ".exr" for f in frames}


def test_a_temporary_of_a_running_process_is_left_alone(tmp_path):
    from lenslab.atomic import HOST
    from lenslab.staging import sweep

    out = tmp_path / "out"
    out.mkdir()
    alive = out / f".frame000.tmp-{os.getpid()}-{HOST}-0123abcd.exr"  # this process runs
    alive.write_bytes(b"being written")
    ended = int(subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True,
                               text=True).stdout)  # that process has ended (and was reaped)
    dead = out / f".frame001.tmp-{ended}-{HOST}-0123abcd.exr"
    dead.write_bytes(b"left by a killed writer")
    older = out / f".frame002.tmp-{ended}-89abcdef.exr"  # named before names carried the machine
    older.write_bytes(b"left by a killed writer")
    elsewhere = out / f".frame003.tmp-{ended}-{'0' if HOST[0] != '0' else '1'}{HOST[1:]}-0123abcd.exr"
    elsewhere.write_bytes(b"being written by a worker on another machine")  # its pid means nothing here
    other = out / ".notes.tmp-1-xyz.txt"  # not a lenslab temporary: the name does not match
    other.write_bytes(b"")
    assert sorted(sweep([out])) == sorted([dead, older])
    assert alive.exists() and elsewhere.exists() and other.exists()


def test_a_batch_started_under_nohup_goes_on_after_sighup(tmp_path):
    frames = _frames(tmp_path / "in", 6)
    out = tmp_path / "out"

    def ignore_hangup():  # what nohup does before it starts the command
        default_stop_signals()
        signal.signal(signal.SIGHUP, signal.SIG_IGN)

    proc = subprocess.Popen(_warp(tmp_path, "--jobs", "1", "-q"), stderr=subprocess.PIPE, text=True,
                            preexec_fn=ignore_hangup)
    try:
        _wait_for(lambda: len(_outputs(out)) >= 1, proc)
        proc.send_signal(signal.SIGSTOP)
        assert proc.poll() is None
        proc.send_signal(signal.SIGHUP)
        proc.send_signal(signal.SIGCONT)
        _, err = proc.communicate(timeout=HANG_GUARD)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 0, err
    assert _outputs(out) == {f.stem + ".exr" for f in frames}
