"""``tracer render`` ends on SIGTERM and SIGHUP as on Ctrl-C (exit 128 + the signal, one line, nothing
written, no temporary), and sweeps the temporaries that killed renders left in its output folders.

Waits are for states, never durations: the render is under way once its progress bar shows on the
terminal (a pseudo-terminal here), and a process stopped by SIGSTOP cannot finish between that and the
signal.
"""

from __future__ import annotations

import fcntl
import os
import pty
import signal
import struct
import subprocess
import sys
import termios
import time

import pytest

from tests.child_signals import default_stop_signals

pytestmark = pytest.mark.slow

HANG_GUARD = 300  # seconds: only against a test that would otherwise wait forever on a broken build
TRACER = [sys.executable, "-c", "import sys; from tracer.cli import main; sys.exit(main())"]


def _read_until(fd: int, proc, marker: bytes) -> bytes:
    """What the process writes on the terminal ``fd``, up to ``marker`` (a state of the process)."""
    import select

    seen = b""
    deadline = time.monotonic() + HANG_GUARD
    while marker not in seen:
        assert proc.poll() is None, f"the render ended before showing {marker!r}: {seen[-300:]!r}"
        assert time.monotonic() < deadline, "hang guard"
        ready, _, _ = select.select([fd], [], [], 1.0)
        if ready:
            seen += os.read(fd, 4096)
    return seen


def _drain(fd: int) -> bytes:
    out = b""
    while True:
        try:
            chunk = os.read(fd, 4096)
        except OSError:  # EIO: the terminal's other side is closed
            return out
        if not chunk:
            return out
        out += chunk


@pytest.mark.parametrize("sig,code,name", [(signal.SIGTERM, 143, "SIGTERM"), (signal.SIGHUP, 129, "SIGHUP"),
                                           (signal.SIGINT, 130, "Ctrl-C")])
def test_a_stop_signal_mid_render_ends_it_like_ctrl_c(tmp_path, sig, code, name):
    out = tmp_path / "out"
    out.mkdir()
    master, slave = pty.openpty()
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 40, 120, 0, 0))  # a terminal 120 columns wide
    argv = TRACER + ["render", "--scene", "cornell", "--size", "64x64", "--spp", "1000000", "-o", str(out / "r.exr"),
                     "--variance-out", str(out / "v.exr")]
    proc = subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=slave,
                            start_new_session=True, preexec_fn=default_stop_signals)
    os.close(slave)
    try:
        shown = _read_until(master, proc, b"tracing cornell")  # the render is under way
        proc.send_signal(signal.SIGSTOP)  # frozen: it cannot finish before the signal
        assert proc.poll() is None
        proc.send_signal(sig)
        proc.send_signal(signal.SIGCONT)
        proc.wait(timeout=HANG_GUARD)
        shown += _drain(master)
    finally:
        if proc.poll() is None:
            proc.kill()
        os.close(master)
    text = shown.decode(errors="replace").replace("\r", "\n")
    lines = [line.strip() for line in text.splitlines() if line.strip() and "tracing cornell" not in line]
    assert proc.returncode == code, text[-500:]
    assert lines and lines[-1].endswith(f"tracer render: interrupted ({name}); unfinished outputs removed"), text
    assert "Traceback" not in text
    assert list(out.iterdir()) == []  # no output, no temporary


def _ended_pid() -> int:
    """The process number of a process that has ended (and was reaped)."""
    done = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True)
    return int(done.stdout)


def test_a_render_sweeps_the_temporaries_of_killed_renders(tmp_path):
    from lenslab.atomic import HOST

    out, var = tmp_path / "out", tmp_path / "var"
    out.mkdir()
    var.mkdir()
    ended = _ended_pid()
    dead = [out / f".r.tmp-{ended}-{HOST}-0123abcd.exr", var / f".v.tmp-{ended}-{HOST}-89abcdef.exr"]
    alive = out / f".r.tmp-{os.getpid()}-{HOST}-0123abcd.exr"  # this process runs: its file stays
    for path in [*dead, alive]:
        path.write_bytes(b"left by a render")
    done = subprocess.run(TRACER + ["render", "--scene", "cornell", "--size", "16x16", "--spp", "1", "-q",
                                    "-o", str(out / "r.exr"), "--variance-out", str(var / "v.exr")],
                          capture_output=True, text=True, timeout=HANG_GUARD)
    assert done.returncode == 0, done.stderr
    assert not any(p.exists() for p in dead)
    assert alive.exists()
    assert sorted(p.name for p in out.iterdir()) == sorted(["r.exr", alive.name])
    assert [p.name for p in var.iterdir()] == ["v.exr"]
