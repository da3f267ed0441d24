"""Ctrl-C that lands inside ``threading.Condition.wait`` still ends the command as Ctrl-C: exit 130 (the code
the funnel and docs/jobs.md give Ctrl-C) and the interrupted line last, never "error: RuntimeError".

A KeyboardInterrupt raised between the moment ``Condition.wait`` releases its lock and the moment it starts to
wait leaves the lock released: leaving ``with cond:`` then raises ``RuntimeError: release unlocked lock``,
and that, not the KeyboardInterrupt, is what reaches the callers. On a real pool the window is a few
instructions wide; the child below widens it with a lock whose release, as ``Condition.wait`` calls it,
says "waiting" on stderr and then waits (a Condition.wait of its own) for the signal. The test waits for that
line (a state), sends SIGINT and reads the exit code: no timing is involved.
"""

from __future__ import annotations

import signal
import subprocess
import sys
import textwrap

import pytest

from tests.child_signals import default_stop_signals

HANG_GUARD = 120  # seconds: only against a child that would otherwise wait forever on a broken build

CHILD = textwrap.dedent('''
    import sys
    import threading

    from lenslab.jobs.funnel import run_command

    class WideLock:
        """A lock whose release inside Condition.wait waits for the signal: the interrupt lands there."""

        def __init__(self):
            self.lock = threading.Lock()

        def acquire(self, *args):
            return self.lock.acquire(*args)

        def release(self):
            self.lock.release()  # released already by the interrupted wait: RuntimeError

        def __enter__(self):
            return self.acquire()

        def __exit__(self, *exc):
            self.release()

        def _is_owned(self):
            return self.lock.locked()

        def _release_save(self):
            self.lock.release()
            print("waiting", file=sys.stderr, flush=True)
            threading.Event().wait()

        def _acquire_restore(self, state):
            self.lock.acquire()

    def wait_in_condition():
        cond = threading.Condition(WideLock())
        try:
            with cond:
                cond.wait()
        except RuntimeError as exc:
            if CHAIN == "cut":  # a library that reports its broken wait as its own error, the cause dropped
                raise RuntimeError(f"the pool's wait failed: {exc}") from None
            raise

    class Job:  # a batch's job whose file waits on a condition
        def run(self, src, dst, progress=None):
            wait_in_condition()

    def batch():
        from lenslab.jobs.runner import execute

        src, dst, error, notes = execute(Job(), "in.exr", "out.exr")
        print(f"lenslab wait: error: {error}", file=sys.stderr)  # what a batch reports for a failed file
        return 1

    CHAIN, WHERE = sys.argv[1], sys.argv[2]
    code = run_command("lenslab wait", wait_in_condition if WHERE == "command" else batch)
    from lenslab.errors import stop_signal

    print(stop_signal(RuntimeError("a later error of the library")))  # the signal is the ended command's only
    sys.exit(code)
''')


@pytest.mark.parametrize("where", ["command", "batch file"])
@pytest.mark.parametrize("chain", ["kept", "cut"])
def test_ctrl_c_inside_a_condition_wait_exits_130_with_the_interrupted_line(chain, where):
    proc = subprocess.Popen([sys.executable, "-c", CHILD, chain, where.split()[0]], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, preexec_fn=default_stop_signals)
    try:
        assert proc.stderr.readline() == "waiting\n"  # blocks until the child is inside the wait
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=HANG_GUARD)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 130, err
    assert err.strip().splitlines() == ["lenslab wait: interrupted (Ctrl-C); unfinished outputs removed"], err
    assert out == "None\n"  # once the command has ended, an error is an error again (a notebook goes on)
