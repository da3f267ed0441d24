"""The ``lenslab`` console command ends without the interpreter's teardown (lenslab.cli.process_exit), and
nothing a user or a library can see changes: exit codes, standard output and error (C's stdio included), output
files, ``atexit`` handlers and non-daemon threads.

Each check runs the command in a child process, as a user does, and compares it with what the same command gives
through :func:`lenslab.cli.main.main` in this process, or with the file the standard library reads back. No check
depends on timing: the thread below waits for a state (the main thread finished), not for a duration.
"""

from __future__ import annotations

import contextlib
import io
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np

from lenslab.cli.main import main
from lenslab.io import read, write
from tests.child_signals import default_stop_signals

HANG_GUARD = 300  # seconds: only against a child that would otherwise never end on a broken build


def _child(code: str, *args: str, **kw) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code), *args], capture_output=True, text=True,
                          timeout=HANG_GUARD, **kw)


def _image(path: Path) -> Path:
    rng = np.random.default_rng(3)
    write(path, rng.random((32, 64, 3), dtype=np.float32))
    return path


def test_stdout_of_a_command_is_what_main_prints():
    res = subprocess.run([sys.executable, "-m", "lenslab", "lenses"], capture_output=True, text=True,
                         timeout=HANG_GUARD)
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        assert main(["lenses"]) == 0
    assert res.returncode == 0, res.stderr
    assert res.stdout == buf.getvalue() and len(res.stdout) > 1000  # all of it: more than one pipe buffer's line
    assert res.stderr == ""


def test_a_warp_writes_its_output_and_atexit_handlers_and_threads_still_run(tmp_path):
    src = _image(tmp_path / "in.exr")
    out, mark, thread_mark = tmp_path / "out.exr", tmp_path / "atexit.txt", tmp_path / "thread.txt"
    res = _child("""
        import atexit, sys, threading, time

        mark, thread_mark = sys.argv[1], sys.argv[2]
        # a library's handler and a library's non-daemon thread, which writes once the main thread is done
        atexit.register(lambda: open(mark, "w").write("ran"))

        def late():
            while threading.main_thread().is_alive():
                time.sleep(0.001)
            open(thread_mark, "w").write("joined")

        threading.Thread(target=late, daemon=False).start()
        import ctypes
        ctypes.CDLL(None).printf(b"printed by C\\n")  # C's stdout: fully buffered on a pipe
        sys.argv = ["lenslab", "warp", sys.argv[3], "-o", sys.argv[4], "--to", "fisheye:fov=180",
                    "--size", "24x24", "-q"]
        from lenslab.cli.main import console
        console()
        raise AssertionError("console() returned")
        """, str(mark), str(thread_mark), str(src), str(out))
    assert res.returncode == 0, res.stderr
    assert mark.read_text() == "ran"
    assert thread_mark.read_text() == "joined"
    assert res.stdout == "printed by C\n"
    assert "AssertionError" not in res.stderr
    assert main(["warp", str(src), "-o", str(tmp_path / "in_process.exr"), "--to", "fisheye:fov=180",
                 "--size", "24x24", "-q"]) == 0
    assert np.array_equal(read(out)[0], read(tmp_path / "in_process.exr")[0])
    assert not [p.name for p in tmp_path.iterdir() if ".tmp-" in p.name]


def test_failed_input_and_usage_error_keep_their_codes_and_lines(tmp_path):
    missing = subprocess.run([sys.executable, "-m", "lenslab", "warp", str(tmp_path / "nothing.exr"), "-o",
                              str(tmp_path / "o.exr"), "--to", "fisheye"], capture_output=True, text=True,
                             timeout=HANG_GUARD)
    assert missing.returncode == 1
    assert missing.stderr.startswith("lenslab warp: error: ") and missing.stderr.count("\n") == 1, missing.stderr
    usage = subprocess.run([sys.executable, "-m", "lenslab", "warp", "--no-such-option"], capture_output=True,
                           text=True, timeout=HANG_GUARD)  # argparse's SystemExit
    assert usage.returncode == 2
    assert usage.stderr.startswith("lenslab warp: error: ") and usage.stderr.count("\n") == 1, usage.stderr
    spec = subprocess.run([sys.executable, "-m", "lenslab", "warp", str(_image(tmp_path / "in.exr")), "-o",
                           str(tmp_path / "o.exr"), "--to", "no-such-lens"], capture_output=True, text=True,
                          timeout=HANG_GUARD)  # the funnel's usage code, returned by main()
    assert spec.returncode == 2
    assert spec.stderr.startswith("lenslab warp: error: ") and "no-such-lens" in spec.stderr, spec.stderr
    assert not (tmp_path / "o.exr").exists()
    assert "Traceback" not in missing.stderr + usage.stderr + spec.stderr


def test_ctrl_c_in_a_command_exits_130(tmp_path):
    """The funnel's interruption (Ctrl-C raised inside the command) still ends the process with 130 and its line."""
    src = _image(tmp_path / "in.exr")
    res = _child("""
        import signal, sys
        import lenslab.jobs.warp as job

        def interrupted(*a, **k):
            signal.raise_signal(signal.SIGINT)

        job.run_warp = interrupted
        import lenslab.cli.warp as cmd
        cmd.run = lambda args: interrupted()
        sys.argv = ["lenslab", "warp", sys.argv[1], "-o", sys.argv[2], "--to", "fisheye"]
        from lenslab.cli.main import console
        console()
        """, str(src), str(tmp_path / "o.exr"), preexec_fn=default_stop_signals)
    assert res.returncode == 128 + signal.SIGINT, res.stderr
    assert res.stderr.strip().splitlines()[-1] == "lenslab warp: interrupted (Ctrl-C); unfinished outputs removed"


def test_a_closed_pipe_still_ends_quietly():
    res = subprocess.run(["bash", "-o", "pipefail", "-c", f"'{sys.executable}' -m lenslab lenses | head -c 10"],
                         capture_output=True, text=True, timeout=HANG_GUARD)
    assert res.returncode == 0, res.stderr
    assert len(res.stdout) == 10
    assert res.stderr == ""
