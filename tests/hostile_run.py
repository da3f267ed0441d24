"""Run lenslab (a command, or the readers on many files in one process) in a subprocess under an
address-space limit, with a timeout used only as a hang guard."""

from __future__ import annotations

import os
import resource
import subprocess
import sys

#: address space of each run: lenslab with NumPy, OpenCV, OpenEXR and numba's LLVM (which reserves a few
#: hundred MB of address space) runs a small warp in under 1 GiB; 1.5 GiB leaves room, and is far below
#: what any refused file would take (4.6 GB and more)
ADDRESS_SPACE = 3 << 29
#: a hang guard only: the runs take seconds; a loop or a stalled read would never end
HANG_GUARD = 600


def _limit():
    resource.setrlimit(resource.RLIMIT_AS, (ADDRESS_SPACE, ADDRESS_SPACE))


def run(argv: list[str], cwd=None, env=None) -> subprocess.CompletedProcess:
    """Run ``argv`` under the address-space limit; the result also has ``peak_mb``, the child's peak
    resident memory (``getrusage`` through ``wait4``) in MB."""
    import signal
    import tempfile

    from lenslab.bench.memory import launched, read_peak_mb

    env = dict(os.environ if env is None else env, PYTHONFAULTHANDLER="1")
    with tempfile.TemporaryDirectory(prefix="lenslab-hostile-run-") as scratch:
        peak = os.path.join(scratch, "peak")
        proc = subprocess.Popen(launched(argv, peak), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                preexec_fn=_limit, cwd=cwd, env=env, start_new_session=True)
        try:
            out, err = proc.communicate(timeout=HANG_GUARD)
        except subprocess.TimeoutExpired:  # a hang: the command and its launcher go
            os.killpg(proc.pid, signal.SIGKILL)
            out, err = proc.communicate()
        done = subprocess.CompletedProcess(argv, proc.returncode, out, err)
        done.peak_mb = read_peak_mb(peak)
    return done


#: reads each file named on the command line; prints "OK name" / "REFUSED name" / "BAD name: type: message"
DRIVER = r'''
import sys, warnings
warnings.simplefilter("ignore")
from lenslab.errors import LenslabError
kind = sys.argv[1]
if kind == "image":
    from lenslab.io import read
else:
    from lenslab.calibfiles import read_lenses as read
for name in sys.argv[2:]:
    print("READ", name, flush=True)
    try:
        read(name)
        print("OK", name, flush=True)
    except (LenslabError, OSError) as exc:
        text = str(exc)
        print("REFUSED" if "\n" not in text and len(text) < 600 else "LONG", name, flush=True)
    except Exception as exc:
        print("BAD", name + ":", type(exc).__name__ + ":", str(exc)[:200].replace("\n", " "), flush=True)
'''


def read_many(kind: str, paths) -> subprocess.CompletedProcess:
    return run([sys.executable, "-c", DRIVER, kind, *map(str, paths)])
