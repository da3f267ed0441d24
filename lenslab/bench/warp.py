"""Warp benchmark: the warp's speed, memory and accuracy aims, each printed with its figure and met/missed and recorded for --json.

Speed, one thread: a 4096x2048 float RGB equirect (a real panorama, enlarged) into a 1024x1024 180 deg
fisheye. The baseline is cv2.remap (bilinear, float32 maps computed beforehand) on the same data in the
same run, timed interleaved with the cases; figures are ratios to it (aims: one-shot bilinear, map
included, within 2x; cached map within 1.2x; --antialias within 4x; 2x2 and 4x4 supersampling without aim).

A photo into a panorama (:mod:`lenslab.bench.warp_photo`): a 2040x1536 pinhole into a 3540x1770 equirect, one
thread, one-shot against cv2.remap of the same map (aim: 2x).

Threads: the same source into a 4096x4096 output, one-shot and --antialias, two threads against one
(aim: at least 1.7x).

Accuracy: every real panorama of ``--data`` (1024x512) into a 256x256 fisheye, relative L1 against an
independent float64 reference (:mod:`lenslab.bench.warp_reference`: the bilinear source averaged over
each output pixel, 16x16 strata, written apart from the engine); aim for --antialias on each: 0.3%
(supersampling figures on forest and courtyard). --antialias against single-tap, one-shot at 4096x2048 ->
1024x1024, one thread: aim 2x.

``--big``: a 16384x8192 source into an 8192x8192 output in a fresh process per thread count, peak RSS
beyond source + output (aim: 300 MB on any thread count).
"""

from __future__ import annotations

import argparse
from pathlib import Path

DATA = Path(__file__).resolve().parents[2].parent / "shared" / "data" / "hdri"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    from lenslab.jobs.arguments import positive_int

    parser.add_argument("--repeat", type=positive_int, default=5, help="timed runs per case (the best counts; default 5)")
    parser.add_argument("--data", type=Path, default=DATA,
                        help="folder of the real panoramas (*.exr; default: ../shared/data/hdri)")
    parser.add_argument("--dst", default="fisheye:fov=180", help="output lens spec (default fisheye:fov=180)")
    parser.add_argument("--big", action="store_true",
                        help="also warp a 16384x8192 source into 8192x8192 and report peak memory (slow, ~3 GB)")
    parser.add_argument("--skip-speed", action="store_true", help="accuracy (and --big) only")
    parser.add_argument("--skip-threads", action="store_true", help="leave out the two-thread figures (slow)")
    parser.add_argument("--only-threads", action="store_true",
                        help="the two-thread figures alone (with the machine's own two-thread ceiling)")
    parser.add_argument("--only-filters", action="store_true",
                        help="only the Lanczos and bicubic one-shot warps against cv2.remap's, one thread (a few "
                             "seconds; a whole run includes them)")
    parser.add_argument("--skip-accuracy", action="store_true",
                        help="leave out the accuracy on the real panoramas (slow: a float64 reference for each)")


def _read(path: Path):
    try:
        from lenslab.io import read
    except ImportError:  # pragma: no cover - the I/O package is part of lenslab
        import OpenEXR
        import numpy as np

        with OpenEXR.File(str(path)) as f:
            return np.ascontiguousarray(f.parts[0].channels["RGB"].pixels, dtype=np.float32)
    return read(path)[0][..., :3]


def _threads(n: int) -> None:
    import cv2

    from lenslab.warp.kernels.dispatch import set_threads

    cv2.setNumThreads(n)
    set_threads(n)


def speed(args) -> None:
    import cv2
    import numpy as np

    from lenslab.bench.results import figure, mark
    from lenslab.bench.timing import ratio_line
    from lenslab.lenses import Camera
    from lenslab.warp import WarpPlan, exact_map, warp
    from lenslab.warp.kernels.dispatch import default_threads

    pano = _read(args.data / "forest.exr")
    src_img = np.ascontiguousarray(cv2.resize(pano, (4096, 2048), interpolation=cv2.INTER_CUBIC), np.float32)
    src = Camera.from_spec("equirect", (4096, 2048))
    dst = Camera.from_spec(args.dst, (1024, 1024))
    g = dst.pixel_grid()[..., 0, :]
    xy, valid = exact_map(src, dst, g)
    mx = np.where(valid, xy[..., 0] - 0.5, -10.0).astype(np.float32)
    my = np.where(valid, xy[..., 1] - 0.5, -10.0).astype(np.float32)
    warp(src_img[:64, :128], Camera.from_spec("equirect", (128, 64)), Camera.from_spec(args.dst, (64, 64)),
         antialias=True)  # compile outside the timings
    print(f"speed: 4096x2048 float RGB equirect -> 1024x1024 {args.dst}, one thread, best of {args.repeat}")
    _threads(1)
    plan = WarpPlan(src, dst, cache=True)
    plan.run(src_img)
    cases = [
        ("baseline", None, None, lambda: cv2.remap(src_img, mx, my, cv2.INTER_LINEAR)),
        ("one-shot bilinear (map included)", "warp.one_shot", 2.0, lambda: warp(src_img, src, dst)),
        ("cached map bilinear", "warp.cached", 1.2, lambda: plan.run(src_img)),
        ("one-shot --antialias", "warp.antialias", 4.0, lambda: warp(src_img, src, dst, antialias=True)),
        ("one-shot 2x2 supersampling", "warp.ss2x2", None, lambda: warp(src_img, src, dst, samples=4)),
        ("one-shot 4x4 supersampling", "warp.ss4x4", None, lambda: warp(src_img, src, dst, samples=16)),
    ]
    best = interleaved([(c[0], c[3]) for c in cases], args.repeat)
    base = best["baseline"]
    print(f"-- baseline cv2.remap bilinear, precomputed maps: {base * 1e3:.2f} ms")
    figure("warp.remap_ms", "cv2.remap 4096x2048 -> 1024x1024, one thread", base * 1e3, "ms", better="lower")
    for label, key, aim, _ in cases[1:]:
        ok = figure(key, f"{label} vs cv2.remap, one thread", best[label] / base, "x", aim=aim)
        print(ratio_line(label, best[label], base, "" if aim is None else f"aim {aim:g}x  {mark(ok)}"))
    aa = best["one-shot --antialias"] / best["one-shot bilinear (map included)"]
    ok = figure("warp.antialias_vs_one_shot", "one-shot --antialias vs one-shot single-tap bilinear, one thread", aa,
                "x", aim=2.0)
    print(f"  --antialias vs single-tap one-shot: {aa:5.2f}x   aim <= 2x  {mark(ok)}")
    antialias_stages(src_img, src, dst, args.repeat)
    _threads(default_threads())
    ours = warp(src_img, src, dst)[0]
    theirs = cv2.remap(src_img, mx, my, cv2.INTER_LINEAR)
    m = valid[..., None] & np.ones(3, bool)
    diff = np.abs(ours - theirs)[m]
    rel = diff / np.maximum(np.abs(ours[m]), 1e-3 * np.abs(ours[m]).mean())
    print(f"cv2.remap's 1/32-pixel weights vs exact bilinear: relative L1 {diff.sum() / np.abs(ours[m]).sum():.2e}; "
          f"per pixel relative difference: 99.9th percentile {np.percentile(rel, 99.9):.2%}, max {rel.max():.1%} "
          f"(largest absolute {diff.max():.3g})")


def antialias_stages(src_img, src, dst, repeat: int) -> None:
    """Where one-shot --antialias spends its time, one thread, in CPU milliseconds (``time.process_time``,
    less disturbed by other processes than wall time; best of ``repeat``, stages interleaved): the map with
    the footprints (and the rim's pixels split and mapped exactly), the rows of the pyramid's coarser levels
    that the footprints read, the footprint filter."""
    import time

    import numpy as np

    from lenslab.bench.results import figure
    from lenslab.warp import antialias as aa
    from lenslab.warp.engine import WarpPlan
    from lenslab.warp.pyramid import ensure_band

    plan = WarpPlan(src, dst, antialias=True)
    out = np.zeros(plan.out_shape + (src_img.shape[2],), np.float32)
    alpha = np.zeros(plan.out_shape, np.float32)
    bands = list(plan.bands())

    def levels():  # the pyramid's rows the footprints read (the warp builds them as its bands need them)
        pyr = aa.pyramid(src_img, plan.border, lazy=True)
        for b in bands:
            ensure_band(pyr, b)
        return pyr

    pyr = levels()

    def cpu(fn):
        t0 = time.process_time()
        fn()
        return time.process_time() - t0

    stages = {
        "map and footprints": lambda: list(plan.bands()),
        "pyramid": levels,
        "footprint filter": lambda: [aa.sample_footprint(pyr, b, plan.border, out[b.r0:b.r1], alpha[b.r0:b.r1])
                                     for b in bands],
    }
    best = {k: float("inf") for k in stages}
    for _ in range(max(1, repeat)):
        for k, fn in stages.items():
            best[k] = min(best[k], cpu(fn))
    print("  --antialias stages, one thread, CPU time: " + ", ".join(f"{k} {v * 1e3:.1f} ms" for k, v in best.items()))
    for k, v in best.items():
        figure("warp.antialias_cpu_" + k.split()[0], f"--antialias stage: {k}, one thread, CPU", v * 1e3, "ms",
               detail=True)


def interleaved(cases, repeat: int) -> dict[str, float]:
    """Best wall time of each ``(label, fn)``; every round times each case once, so that a burst of load
    from other processes hits the baseline and the cases alike."""
    from lenslab.bench.timing import best_time

    best = {label: float("inf") for label, _ in cases}
    for _ in range(max(1, repeat)):
        for label, fn in cases:
            best[label] = min(best[label], best_time(fn, 1))
    return best


def thread_scaling(args) -> None:
    """Two threads against one at a 4096x4096 output (:mod:`lenslab.bench.warp_threads`)."""
    import cv2
    import numpy as np

    from lenslab.bench.warp_threads import thread_scaling as run

    def source():
        pano = _read(args.data / "forest.exr")
        return np.ascontiguousarray(cv2.resize(pano, (4096, 2048), interpolation=cv2.INTER_CUBIC), np.float32)

    run(args, _threads, source)


def accuracy(args) -> None:
    import time

    import numpy as np

    from lenslab.bench.results import figure, mark
    from lenslab.bench.warp_reference import reference
    from lenslab.lenses import Camera
    from lenslab.warp import warp

    fov = 180.0
    dst = Camera.from_spec(f"fisheye:fov={fov:g}", (256, 256))
    paths = sorted(args.data.glob("*.exr"))
    if not paths:
        print(f"accuracy: no panorama (*.exr) in {args.data}, skipped")
    worst = None
    for path in paths:  # every real panorama; the aim holds on each
        name, aim = path.stem, 0.3
        img = _read(path)
        src = Camera.from_spec("equirect", (img.shape[1], img.shape[0]))
        ref = reference(img, 256, fov)
        total = np.abs(ref).sum()
        print(f"accuracy: {name}.exr {img.shape[1]}x{img.shape[0]} -> 256x256 fisheye:fov={fov:g}, relative L1 vs "
              "an independent float64 box average of the bilinear source (16x16 strata)")
        rows = []
        cases = (("single_tap", "single-tap bilinear", {}), ("ss2x2", "2x2 supersampling", {"samples": 4}),
                 ("ss4x4", "4x4 supersampling", {"samples": 16}), ("antialias", "--antialias", {"antialias": True}))
        if name not in ("forest", "courtyard"):  # the others: single tap and --antialias
            cases = cases[:1] + cases[3:]
        for key, label, kw in cases:
            out = warp(img, src, dst, **kw)[0]
            best = float("inf")
            for _ in range(max(1, args.repeat)):
                t0 = time.perf_counter()
                warp(img, src, dst, **kw)
                best = min(best, time.perf_counter() - t0)
            rows.append((key, label, 100.0 * np.abs(out - ref).sum() / total, best))
        for key, label, err, t in rows:
            a = aim if key == "antialias" else None
            ok = figure(f"warp.error_{name}_{key}", f"{name}.exr {label}, relative L1 vs independent reference",
                        err, "%", aim=a)
            print(f"  {label:<24s} {err:8.3f}%   time {t / rows[0][3]:6.2f}x single-tap"
                  + ("" if a is None else f"   aim <= {a:g}%  {mark(ok)}"))
        err = rows[-1][2]
        worst = (err, name) if worst is None or err > worst[0] else worst
    if worst is not None:
        ok = figure("warp.error_worst_antialias", f"--antialias, worst of {len(paths)} real panoramas ({worst[1]}), "
                    "relative L1 vs independent reference", worst[0], "%", aim=0.3)
        print(f"accuracy: --antialias worst of {len(paths)} panoramas: {worst[1]} {worst[0]:.3f}%   aim <= 0.3%  "
              f"{mark(ok)}")


BIG_SCRIPT = """
import resource, sys, numpy as np
from lenslab.warp.kernels.dispatch import set_threads
set_threads(int(sys.argv[1]))
from lenslab.lenses import Camera
from lenslab.warp import warp
src_img = np.zeros((8192, 16384, 3), dtype=np.float32)
src_img[::7, ::5] = 1.0
base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
out, alpha = warp(src_img, Camera.from_spec("equirect", (16384, 8192)), Camera.from_spec(sys.argv[2], (8192, 8192)))
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
print(base, peak, src_img.nbytes, out.nbytes + alpha.nbytes)
"""


def big(args) -> None:
    """Peak RSS of a 16384x8192 -> 8192x8192 warp beyond source + output, in a fresh process per thread
    count (the peak of a process never comes down)."""
    import subprocess
    import sys
    import time

    from lenslab.bench.results import figure, mark

    mb = 1 / 2**20
    print(f"big: 16384x8192 float RGB -> 8192x8192 {args.dst}, peak RSS beyond source + output + alpha")
    for n in (1, 2):
        t0 = time.perf_counter()
        res = subprocess.run([sys.executable, "-c", BIG_SCRIPT, str(n), args.dst], capture_output=True, text=True)
        if res.returncode != 0:
            print(f"  {n} thread(s): failed: {res.stderr.strip().splitlines()[-1:]}")
            continue
        base, peak, src_bytes, out_bytes = map(int, res.stdout.split()[-4:])
        # base: the interpreter, numpy, numba and the source; what the warp adds beyond its output
        extra = (peak - base - out_bytes) * mb
        ok = figure(f"warp.big_rss_{n}t", f"16384x8192 -> 8192x8192, {n} thread(s): peak RSS beyond source + output",
                    extra, "MB", aim=300.0)
        print(f"  {n} thread(s): {time.perf_counter() - t0:.1f} s, peak RSS {peak * mb:.0f} MiB = before the warp "
              f"{base * mb:.0f} MiB (source {src_bytes * mb:.0f}) + output {out_bytes * mb:.0f} MiB + "
              f"{extra:.0f} MiB   aim <= 300  {mark(ok)}")


def _source(args):
    """The speed cases' 4096x2048 float32 RGB source: forest.exr enlarged, or smooth noise without the data."""
    import cv2
    import numpy as np

    path = args.data / "forest.exr"
    small = _read(path) if path.is_file() else np.random.default_rng(0).random((64, 128, 3)).astype(np.float32)
    return np.ascontiguousarray(cv2.resize(small, (4096, 2048), interpolation=cv2.INTER_CUBIC), np.float32)


def run(args: argparse.Namespace) -> int:
    if args.only_filters:
        from lenslab.bench.warp_filters import filter_speed

        filter_speed(args, lambda: _source(args))
        return 0
    if args.only_threads:
        thread_scaling(args)
        return 0
    if not args.skip_speed:
        speed(args)
        from lenslab.bench.warp_filters import filter_speed

        filter_speed(args, lambda: _source(args))
        from lenslab.bench.warp_photo import photo_speed

        photo_speed(args, lambda: _source(args))
        if not args.skip_threads:
            thread_scaling(args)
    if not args.skip_accuracy:
        accuracy(args)
    if args.big:
        big(args)
    return 0
