"""Start-up: the wall time of whole commands on one small image, as a user waits for them.

``lenslab convert``, ``lenslab tonemap`` and ``lenslab warp`` each run on one 256 x 128 EXR panorama
(written first to a temporary directory), as separate processes, the median of --repeat runs after
one warm-up run that is not counted (a warm machine: Python's bytecode and numba's kernel caches are
filled, so the child processes may write them even where this shell forbids it). The aim is 0.4 s
for each. The baseline, measured in the same run, is ``python -c "import numpy"``: the floor any
command of lenslab starts from.

First compile (skip with ``--no-first-compile``): what a new machine spends compiling kernels before its
first warps (``lenslab demo`` warps into every lens first): a fresh process with an empty numba cache
(``NUMBA_CACHE_DIR`` set to a new folder) warps a 512 x 256 panorama into every lens of ``lenslab bench
lenses`` at 128 x 128 with ``--antialias`` (the demo's setting), twice each; the first calls' time
beyond the second calls' is the compiling. The aim is 3 s.
"""

from __future__ import annotations

import argparse

AIM_SECONDS = 0.4
AIM_FIRST_COMPILE = 3.0  # seconds of compiling before the first warps into every lens, new machine

# run with an empty NUMBA_CACHE_DIR: warp into each lens twice; print the first calls' excess per lens
FIRST_COMPILE_SCRIPT = """
import json, sys, time
import numpy as np
from lenslab.bench.lenses import DEFAULT_SPECS
from lenslab.lenses import Camera
from lenslab.warp import warp
pano = (0.18 * np.exp2(np.random.default_rng(0).normal(0.0, 2.0, (256, 512, 3)))).astype(np.float32)
src = Camera.from_spec("equirect", (512, 256))
excess = {}
cpu = 0.0
for spec in DEFAULT_SPECS:
    cam = Camera.from_spec(spec, (128, 128))
    t0, c0 = time.perf_counter(), time.process_time()
    warp(pano, src, cam, antialias=True, allow_parallax=True)
    t1, c1 = time.perf_counter(), time.process_time()
    warp(pano, src, cam, antialias=True, allow_parallax=True)
    excess[spec] = max(0.0, (t1 - t0) - (time.perf_counter() - t1))
    cpu += max(0.0, (c1 - c0) - (time.process_time() - c1))
print(json.dumps({"excess": excess, "cpu": cpu}))
"""

COMMANDS = {
    "convert": ["convert", "{src}", "--to", "png", "-o", "{dir}/out.png", "--overwrite"],
    "tonemap": ["tonemap", "{src}", "-o", "{dir}/out.jpg", "--overwrite"],
    "warp": ["warp", "{src}", "-o", "{dir}/out.exr", "--to", "fisheye:fov=180", "--size", "128x128",
             "--overwrite"],
}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    from lenslab.jobs.arguments import positive_int

    parser.add_argument("--repeat", type=positive_int, default=7, help="runs per command; the median is reported (default 7)")
    parser.add_argument("--commands", default=",".join(COMMANDS),
                        help=f"comma-separated commands to time (default {','.join(COMMANDS)})")
    parser.add_argument("--no-first-compile", dest="first_compile", action="store_false",
                        help="leave out the first-compile figure (a fresh process compiling the lenses' numba kernels, "
                             "several seconds)")


def wall_times(argv: list[str], repeat: int, env: dict) -> list[float]:
    """Wall times of ``repeat`` runs of ``argv`` after one uncounted warm-up; a failed run raises."""
    import subprocess
    import time

    times = []
    for i in range(repeat + 1):
        t0 = time.perf_counter()
        done = subprocess.run(argv, env=env, capture_output=True, text=True)
        elapsed = time.perf_counter() - t0
        if done.returncode != 0:
            raise RuntimeError(f"{' '.join(argv)} failed ({done.returncode}): {done.stderr.strip()[-300:]}")
        if i:
            times.append(elapsed)
    return times


def run(args: argparse.Namespace) -> int:
    import os
    import statistics
    import sys
    import tempfile

    import numpy as np

    from lenslab import io
    from lenslab.bench.results import figure, mark

    names = [n.strip() for n in args.commands.split(",") if n.strip()]
    unknown = [n for n in names if n not in COMMANDS]
    if unknown:
        print(f"lenslab bench startup: unknown command(s) {', '.join(unknown)}; valid: {', '.join(COMMANDS)}",
              file=sys.stderr)
        return 2
    repeat = max(1, args.repeat)
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    with tempfile.TemporaryDirectory(prefix="lenslab-startup-") as tmp:
        src = os.path.join(tmp, "pano.exr")
        rng = np.random.default_rng(0)
        io.write(src, (0.18 * np.exp2(rng.normal(0.0, 2.0, (128, 256, 3)))).astype(np.float32))
        base = statistics.median(wall_times([sys.executable, "-c", "import numpy"], repeat, env))
        print(f"start-up of whole commands on a 256 x 128 image, median of {repeat} runs after a warm-up; "
              f"aim {AIM_SECONDS:g} s each", flush=True)
        label = 'python -c "import numpy" (baseline)'
        print(f"{label:<34s} {base:7.3f} s", flush=True)
        for name in names:
            argv = [sys.executable, "-m", "lenslab"] + [a.format(src=src, dir=tmp) for a in COMMANDS[name]]
            t = statistics.median(wall_times(argv, repeat, env))
            ok = figure(f"startup.{name}", f"lenslab {name} of a 256x128 image, whole process", t, "s",
                        aim=AIM_SECONDS, better="lower", note=f"baseline python -c 'import numpy' {base:.3f} s")
            print(f"{'lenslab ' + name:<34s} {t:7.3f} s  {t / base:5.1f}x baseline  {mark(ok)}", flush=True)
    if args.first_compile:
        first_compile(env)
    return 0


def first_compile(env: dict) -> None:
    """The first-compile figure (see the module docstring)."""
    import json
    import subprocess
    import sys
    import tempfile

    from lenslab.bench.results import figure, mark

    with tempfile.TemporaryDirectory(prefix="lenslab-numba-cache-") as cache:
        done = subprocess.run([sys.executable, "-c", FIRST_COMPILE_SCRIPT], env={**env, "NUMBA_CACHE_DIR": cache},
                              capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"the first-compile run failed ({done.returncode}): {done.stderr.strip()[-300:]}")
    res = json.loads(done.stdout.strip().splitlines()[-1])
    excess, cpu = res["excess"], res["cpu"]
    total = sum(excess.values())
    ok = figure("startup.first_compile", "first warps into every lens on a new machine (empty kernel cache): "
                "compiling", total, "s", aim=AIM_FIRST_COMPILE, better="lower",
                note=f"{len(excess)} lenses, 128x128 with --antialias from a 512x256 panorama; {cpu:.2f} s of CPU")
    figure("startup.first_compile_cpu", "the same, CPU seconds of compiling (less sensitive to a busy machine)", cpu,
           "s", detail=True)
    print(f"{'first compile, every lens':<34s} {total:7.3f} s  (aim {AIM_FIRST_COMPILE:g} s)  {mark(ok)}   "
          f"CPU {cpu:.2f} s", flush=True)
    worst = sorted(excess.items(), key=lambda kv: -kv[1])[:3]
    print("  the lenses whose first warp compiled most: "
          + ", ".join(f"{spec.split(',')[0]} {sec:.2f} s" for spec, sec in worst), flush=True)
