"""Two threads against one, for the warp and for the machine itself.

A 4096x2048 float RGB equirect into a 4096x4096 output, one-shot bilinear and one-shot --antialias (aim:
2 threads at least 1.7x faster than 1). The machine is shared: another process busy on one core leaves a
two-thread run 4/3 of a core more than a one-thread run, not 2. So every round times, in the same process
and one after the other, each case on 1 and on 2 threads (which goes first alternates from round to round),
beside two plain tasks that measure what the machine allows at that moment (its *ceiling*, detail figures):

- ``copy``: ``np.copyto`` of 256 MB, in two halves on two threads (memory bandwidth: this VM's is used up by
  one thread, a two-thread ratio near 1);
- ``compute``: ``np.sin`` over 1M float64 values four times (in two halves on two threads: no memory to
  share, the cores alone).

A figure is the best one-thread time over the best two-thread time (best of the rounds, each taken the same
way: nothing favours either side); the median of the rounds' own ratios and the CPU time of the two-thread
run over the one-thread run's (extra work that threads cost, whatever the load) are printed beside it.
"""

from __future__ import annotations

import statistics
import time


#: rounds of the --antialias case (the others take ``--repeat`` rounds, at most 7)
AA_ROUNDS = 3


def _ceilings():
    """``{name: fn(threads)}`` of the two plain tasks (arrays made once; a pool of two threads kept)."""
    from concurrent.futures import ThreadPoolExecutor

    import numpy as np

    pool = ThreadPoolExecutor(2)
    a = np.ones(1 << 26, np.float32)
    b = np.empty_like(a)
    b.fill(0.0)
    x = np.random.default_rng(0).random(1 << 20)
    y = np.empty_like(x)

    def split(fn, n, size):
        if n == 1:
            fn(0, size)
            return
        futures = [pool.submit(fn, i * size // n, (i + 1) * size // n) for i in range(n)]
        for f in futures:
            f.result()

    def copy(lo, hi):
        np.copyto(b[lo:hi], a[lo:hi])

    def compute(lo, hi):
        for _ in range(4):
            np.sin(x[lo:hi], out=y[lo:hi])

    return {"copy": lambda n: split(copy, n, a.size), "compute": lambda n: split(compute, n, x.size)}


def _pressure() -> str:
    """The kernel's CPU pressure (the share of the last 10 s in which some runnable task waited for a core), when
    this Linux reports it, and the load average."""
    import os

    words = []
    try:
        with open("/proc/pressure/cpu", encoding="ascii") as f:
            some = dict(kv.split("=") for kv in f.readline().split()[1:])
        words.append(f"CPU pressure {float(some['avg10']):.0f}% of the last 10 s")
    except (OSError, ValueError, KeyError):
        pass
    try:
        words.append("load " + " ".join(f"{v:.2f}" for v in os.getloadavg()))
    except OSError:
        pass
    return ", ".join(words) or "load unknown"


def _timed(fn) -> tuple[float, float]:
    """Wall and process CPU seconds of ``fn()``."""
    t0, c0 = time.perf_counter(), time.process_time()
    fn()
    return time.perf_counter() - t0, time.process_time() - c0


def thread_scaling(args, set_threads, read_source) -> None:
    """Print and record the two-thread figures (``set_threads(n)`` sets the warp's and OpenCV's threads)."""
    from lenslab.bench.results import figure, mark
    from lenslab.lenses import Camera
    from lenslab.warp import warp

    src_img = read_source()
    src = Camera.from_spec("equirect", (src_img.shape[1], src_img.shape[0]))
    dst = Camera.from_spec(args.dst, (4096, 4096))
    rounds = max(1, min(args.repeat, 7))
    cases = [("machine.copy", "machine ceiling: np.copyto 256 MB", None),
             ("machine.compute", "machine ceiling: np.sin, 1M float64 x 4", None),
             ("warp.threads_one_shot", "one-shot bilinear", lambda: warp(src_img, src, dst)),
             ("warp.threads_antialias", "one-shot --antialias", lambda: warp(src_img, src, dst, antialias=True))]
    ceil = _ceilings()
    runs = {key: {1: [], 2: []} for key, _, _ in cases}
    print(f"threads: {src_img.shape[1]}x{src_img.shape[0]} -> 4096x4096 {args.dst}, {rounds} rounds ({min(rounds, AA_ROUNDS)} "
          "for --antialias) of 1 and 2 threads in turn, beside the machine's own two-thread ceiling")
    before = _pressure()
    for r in range(rounds):
        for key, _, fn in cases:
            if key == "warp.threads_antialias" and r >= AA_ROUNDS:  # 3-5 s a round on a loaded machine
                continue
            for n in ((1, 2) if r % 2 == 0 else (2, 1)):
                set_threads(n)
                runs[key][n].append(_timed((lambda n=n: ceil[key.split(".")[1]](n)) if fn is None else fn))
    set_threads(2)
    print(f"  machine before: {before}; after: {_pressure()}")
    for key, label, fn in cases:
        one, two = runs[key][1], runs[key][2]
        best1, best2 = min(w for w, _ in one), min(w for w, _ in two)
        speedup = best1 / best2
        median = statistics.median(a[0] / b[0] for a, b in zip(one, two))
        cpu = min(c for _, c in two) / min(c for _, c in one)
        if fn is None:
            figure(f"warp.{key}_2t", f"{label}, 2 threads vs 1 (in the same rounds as the warp)", speedup, "x",
                   better="higher", detail=True)
            print(f"  {label:<40s} 1 thread {best1 * 1e3:8.1f} ms   2 threads {best2 * 1e3:8.1f} ms   {speedup:5.2f}x"
                  f"   (median of rounds {median:.2f}x)")
            continue
        ok = figure(key, f"{label}, 2 threads vs 1 at 4096x4096", speedup, "x", aim=1.7, better="higher")
        figure(key + "_cpu", f"{label}: CPU time of 2 threads over 1 thread's", cpu, "x", detail=True)
        print(f"  {label:<40s} 1 thread {best1 * 1e3:8.0f} ms   2 threads {best2 * 1e3:8.0f} ms   {speedup:5.2f}x"
              f"  aim >= 1.7x  {mark(ok)}   (median of rounds {median:.2f}x; CPU time 2 threads / 1: {cpu:.2f})")
