"""Tracer benchmarks (machines are shared and noisy: figures are ratios against a baseline in the same run).

1. Primary-ray casts on the Cornell box: the tracer's accelerator (triangle ids and distances out)
   against calling embree's ``EmbreeScene.run`` directly on the same float32 rays, with one thread and
   with every thread (the baseline then splits the batch over the same thread pool by hand); and from
   the camera's float64 rays, conversion included.
2. Path tracing the Cornell box at 256x256, max depth 8 bounces (Mitsuba's max_depth 9, which counts
   the camera segment), Russian roulette from bounce 5 as in Mitsuba: samples per second (reference: Mitsuba 3
   renders its Cornell box at about 0.6 Msamples/s with scalar_rgb and 2 with llvm_ad_rgb on a
   machine of this kind).
3. Peak memory of a render at two sample counts: bounded by the batch size, not by spp.
"""

from __future__ import annotations

import argparse
import time


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--size", type=int, default=256, help="image side for the path-tracing figure (default 256)")
    p.add_argument("--spp", type=int, default=16, help="samples per pixel for the path-tracing figure (default 16)")
    p.add_argument("--max-depth", type=int, default=8, help="maximum bounces (default 8)")
    p.add_argument("--rr-depth", type=int, default=5,
                   help="bounces before Russian roulette (default 5, Mitsuba's default, for a like-for-like figure)")
    p.add_argument("--repeat", type=int, default=7, help="timing repeats; the best is kept (default 5)")
    p.add_argument("--threads", type=int, help="threads for the 'all threads' figures (default: every core)")


def _best(fn, repeat: int) -> tuple[float, float]:
    """Best wall time and best process CPU time (all threads) of ``fn()`` over ``repeat`` runs."""
    wall = cpu = float("inf")
    for _ in range(max(1, repeat)):
        w0, c0 = time.perf_counter(), time.process_time()
        fn()
        wall = min(wall, time.perf_counter() - w0)
        cpu = min(cpu, time.process_time() - c0)
    return wall, cpu


def _line(label: str, wall: float, cpu: float, base: tuple[float, float], n: int, unit: str) -> str:
    return (f"  {label:<34s} {wall * 1e3:9.1f} ms wall {cpu * 1e3:9.1f} ms cpu   {n / wall / 1e6:6.2f} M{unit}/s   "
            f"throughput ratio {base[0] / wall:5.2f} wall, {base[1] / cpu:5.2f} cpu")


def run(args) -> int:
    import numpy as np

    from tracer.accel import cpu_count, pool
    from tracer.load import load_scene
    from tracer.rendering import render

    threads = args.threads or cpu_count()
    scene = load_scene("cornell")
    accel = scene.accel
    cam = scene.camera(size=(512, 512))
    o, d, _ = cam.rays(samples=4, seed=0)
    o, d = o.reshape(-1, 3) - scene.shift, d.reshape(-1, 3)  # into the scene's local frame, as the tracer works
    n = len(o)
    o32 = np.ascontiguousarray(o, dtype=np.float32)
    d32 = np.ascontiguousarray(d, dtype=np.float32)
    print(f"primary rays: Cornell box, {n} camera rays (512x512, 4 spp)")
    print("  ratio = baseline time / tracer time (1.0 = no overhead over calling embree directly), on the same")
    print("  float32 rays; the float64 line takes the rays as the camera makes them")
    base1 = _best(lambda: accel.scene.run(o32, d32, output=1), args.repeat)
    print(_line("embree run, 1 thread (baseline)", *base1, base1, n, "rays"))
    ours1 = _best(lambda: accel.intersect(o32, d32, threads=1), args.repeat)
    print(_line("tracer intersect, 1 thread", *ours1, base1, n, "rays"))
    ours64 = _best(lambda: accel.intersect(o, d, threads=1), args.repeat)
    print(_line("tracer intersect float64, 1 thread", *ours64, base1, n, "rays"))
    edges = np.linspace(0, n, threads + 1).astype(int)
    parts = [slice(a, b) for a, b in zip(edges[:-1], edges[1:])]
    baseN = _best(lambda: list(pool().map(lambda s: accel.scene.run(o32[s], d32[s], output=1), parts)), args.repeat)
    print(_line(f"embree run, {threads} threads (baseline)", *baseN, baseN, n, "rays"))
    oursN = _best(lambda: accel.intersect(o32, d32, threads=threads), args.repeat)
    print(_line(f"tracer intersect, {threads} threads", *oursN, baseN, n, "rays"))

    size = args.size
    pcam = scene.camera(size=(size, size))
    render(scene, pcam, spp=1, seed=0, max_depth=args.max_depth, threads=threads, rr_depth=args.rr_depth)  # warm up
    total = args.spp * size * size
    print(f"\npath tracing: Cornell box {size}x{size}, {args.spp} spp, max depth {args.max_depth} "
          f"(Mitsuba's max_depth {args.max_depth + 1}), Russian roulette from bounce {args.rr_depth}, {threads} threads")
    for nt in sorted({1, threads}):
        res = []
        wall, cpu = _best(lambda: res.append(render(scene, pcam, spp=args.spp, seed=len(res), max_depth=args.max_depth,
                                                    threads=nt, rr_depth=args.rr_depth)), max(1, min(args.repeat, 3)))
        print(f"  {nt} thread{'s' if nt > 1 else ' '}: {wall:6.2f} s wall, {total / wall / 1e6:6.3f} Msamples/s "
              f"({total / wall / 0.6e6:4.2f}x Mitsuba scalar_rgb's 0.6 M, {total / wall / 2e6:4.2f}x llvm_ad_rgb's 2 M); "
              f"{total / cpu / 1e6:6.3f} Msamples per CPU second")
    r = res[-1]
    print(f"  mean radiance {np.round(r.image.mean(axis=(0, 1)), 4).tolist()}, relative error {r.relative_error:.4f} "
          f"at {r.spp} spp")
    print("  (Mitsuba figures are reference numbers for this kind of machine, not measured in this run; "
          "on a shared machine compare the per-CPU-second figure)")

    import tracemalloc

    small = scene.camera(size=(128, 128))
    peaks = []
    for spp in (4, 64):
        tracemalloc.start()
        render(scene, small, spp=spp, seed=0, max_depth=args.max_depth, threads=threads, batch=1 << 15)
        peaks.append(tracemalloc.get_traced_memory()[1])
        tracemalloc.stop()
    print(f"\nmemory (128x128, batch 32768 samples): peak {peaks[0] / 2**20:.1f} MiB at 4 spp, "
          f"{peaks[1] / 2**20:.1f} MiB at 64 spp ({peaks[1] / peaks[0]:.2f}x for 16x the samples)")
    return 0
