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
4. ``--vs-mitsuba`` (when Mitsuba 3 is installed; it is not a dependency of the project): whole process,
   ``tracer render --scene cornell`` against a Python process in which Mitsuba 3 ``scalar_rgb`` renders its
   own Cornell box (``mi.cornell_box()``) at the same size, spp and depth (Mitsuba's max_depth is the
   tracer's plus one) and writes it as EXR; ``--runs`` runs each, interleaved; medians of wall and CPU time
   (user + system of the child process), as ratios tracer / Mitsuba (aim: at most 0.6x). Both run as an installed
   package does, with Python's bytecode cached (in the run's scratch folder: a first run of each warms it and the
   page cache up, even where PYTHONDONTWRITEBYTECODE is set). Each renderer keeps
   its own defaults otherwise: the tracer starts Russian roulette at bounce 3 and averages samples in the pixel
   (a box filter); Mitsuba starts it at 5 and splats through a Gaussian filter.

5. ``--validate``: the warp against the direct trace, noise-free (``lenslab validate --noise-free``'s
   pipeline: the Cornell box lit by a point light, fixed sub-pixel sample positions, so the difference is
   the resampling error alone): a 4096x2048 panorama traced from the view's eye, warped into a 512x512
   180-degree equisolid fisheye with single-tap bilinear and with ``--antialias``, against the fisheye traced
   directly at 64 samples per pixel. Figures: each setting's relative L1 over the covered pixels, and the
   antialias warp's time over the single-tap warp's (best of ``--repeat``, at least 2 so that the first
   call's loading stays out, at most 5; same process, same panorama).
   ``--quick`` uses a 1024x512 panorama and a 128x128 fisheye at 16 samples (a smoke run; its figures have
   no aims).

Aims (printed with met/MISSED and written with ``--json FILE``, benchmark name "tracer"): primary rays at
least 0.9x raw embree's throughput on the same rays; the Cornell box within 0.6x Mitsuba's time;
``--antialias`` at or under 0.3% relative L1 against the direct trace at no more than 2x the single-tap
warp's time.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time

AIM_PRIMARY = 0.9  # tracer throughput / raw embree throughput, same rays
AIM_MITSUBA = 0.6  # tracer time / Mitsuba 3 scalar_rgb time, whole process
AIM_VALIDATE_L1 = 0.3  # percent relative L1 of the --antialias warp against the direct trace
AIM_VALIDATE_COST = 2.0  # --antialias warp time / single-tap bilinear warp time

# Mitsuba 3 renders its own Cornell box: argv = size, spp, max_depth (Mitsuba's count), output EXR
MITSUBA_SCRIPT = """
import sys
import mitsuba as mi
mi.set_variant("scalar_rgb")
scene = mi.cornell_box()
scene["integrator"]["max_depth"] = int(sys.argv[3])
scene["sensor"]["film"]["width"] = scene["sensor"]["film"]["height"] = int(sys.argv[1])
scene["sensor"]["sampler"]["sample_count"] = int(sys.argv[2])
mi.util.write_bitmap(sys.argv[4], mi.render(mi.load_dict(scene)))
"""


def add_arguments(p: argparse.ArgumentParser) -> None:
    from lenslab.jobs.arguments import positive_int

    p.add_argument("--size", type=positive_int, default=256, help="image side for the path-tracing figure (default 256)")
    p.add_argument("--spp", type=positive_int, default=16, help="samples per pixel for the path-tracing figure (default 16)")
    p.add_argument("--max-depth", type=int, default=8, help="maximum bounces (default 8)")
    p.add_argument("--rr-depth", type=int, default=5,
                   help="bounces before Russian roulette (default 5, Mitsuba's default, for a like-for-like figure)")
    p.add_argument("--repeat", type=positive_int, default=7, help="timing repeats; the best is kept (default 7)")
    p.add_argument("--threads", type=positive_int, help="threads for the 'all threads' figures (default: every core)")
    p.add_argument("--vs-mitsuba", action="store_true",
                   help="also time the whole 'tracer render' of the Cornell box at --size and 64 spp against Mitsuba 3 "
                        "scalar_rgb rendering its own Cornell box (needs 'import mitsuba'; skipped with a note without it)")
    p.add_argument("--runs", type=positive_int, default=5, help="whole-process runs of each renderer for --vs-mitsuba (default 5)")
    p.add_argument("--mitsuba-only", action="store_true", help="only the --vs-mitsuba figures")
    p.add_argument("--validate", action="store_true",
                   help="also measure the warp against the direct trace: a 4096x2048 panorama of the Cornell box "
                        "(noise-free) into a 512x512 180-degree fisheye, single-tap and --antialias: error and cost")
    p.add_argument("--validate-only", action="store_true", help="only the --validate figures")
    p.add_argument("--quick", action="store_true",
                   help="with --validate: a 1024x512 panorama into 128x128 at 16 spp, a smoke run without aims")
    p.add_argument("--json", metavar="FILE", help="also write every figure, its aim and whether it is met, as JSON")
    p.add_argument("--overwrite", action="store_true", help="replace an existing --json FILE")


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
    from lenslab.bench import results

    if args.quick and not (args.validate or args.validate_only):
        from lenslab.errors import UsageError

        raise UsageError("--quick shortens the --validate figures only; add --validate or --validate-only")
    if args.json:  # refused before the benchmark runs, not after
        from lenslab.jobs.policy import check_output

        check_output(args.json, (), args.overwrite)
    record = results.start()
    only = args.mitsuba_only or args.validate_only
    if not only:
        throughput(args)
    if args.vs_mitsuba or args.mitsuba_only:
        vs_mitsuba(args)
    if args.validate or args.validate_only:
        validation(args)
    if args.json:
        results.write(args.json, "tracer", record, argv=sys.argv[1:], overwrite=args.overwrite)
        print(f"figures written to {args.json}")
    return 0


def throughput(args) -> None:
    import numpy as np

    from lenslab.bench.results import figure, mark

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
    # the aim is for the same rays; the float64 line also converts the camera's rays, so it has no aim
    for key, label, base, ours, aim in (("primary_1_thread", "1 thread", base1, ours1, AIM_PRIMARY),
                                        ("primary_float64_1_thread", "float64 rays in, 1 thread", base1, ours64, None),
                                        ("primary_all_threads", f"{threads} threads", baseN, oursN, AIM_PRIMARY)):
        ok = figure(f"tracer.{key}", f"primary rays, {label}: tracer / raw embree throughput", base[0] / ours[0], "x",
                    aim=aim, better="higher")
        print(f"  {label:<34s} tracer / raw embree throughput {base[0] / ours[0]:5.2f}x"
              + (f" (aim at least {aim}x) {mark(ok)}" if aim else " (conversion included, no aim)"))

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


def _process(cmd: list[str], env: dict | None = None) -> tuple[float, float]:
    """Wall seconds and CPU seconds (the child's user + system) of one whole process."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    done = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, env=env)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode:
        raise RuntimeError(f"{' '.join(cmd[:4])}... failed: {done.stderr.strip()[-400:]}")
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def vs_mitsuba(args, spp: int = 64) -> None:
    import importlib.util

    from lenslab.bench.results import figure, mark

    if importlib.util.find_spec("mitsuba") is None:
        print("\nvs Mitsuba: mitsuba is not installed (it is not a dependency of lenslab; 'pip install mitsuba' "
              "to measure it); figure skipped")
        return
    size = args.size
    with tempfile.TemporaryDirectory(prefix="tracer-bench-") as tmp:
        ours = [sys.executable, "-m", "tracer.cli", "render", "--scene", "cornell", "--size", f"{size}x{size}",
                "--spp", str(spp), "--max-depth", str(args.max_depth), "-o", os.path.join(tmp, "tracer.exr"),
                "--overwrite", "-q"]
        if args.threads:
            ours += ["--threads", str(args.threads)]
        theirs = [sys.executable, "-c", MITSUBA_SCRIPT, str(size), str(spp), str(args.max_depth + 1),
                  os.path.join(tmp, "mitsuba.exr")]
        # both as an installed package runs: Python's bytecode cached (in the scratch folder, whatever
        # PYTHONDONTWRITEBYTECODE says here), files in the page cache, so the first run of each warms them up
        env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
        env["PYTHONPYCACHEPREFIX"] = os.path.join(tmp, "pycache")
        _process(ours, env)
        _process(theirs, env)
        print(f"\nvs Mitsuba 3 scalar_rgb, whole process: Cornell box {size}x{size}, {spp} spp, max depth "
              f"{args.max_depth} bounces (Mitsuba's max_depth {args.max_depth + 1}), {args.runs} runs each, "
              f"interleaved, medians, bytecode cached (load {os.getloadavg()[0]:.2f})")
        runs: dict[str, list[tuple[float, float]]] = {"tracer": [], "mitsuba": []}
        for _ in range(max(1, args.runs)):
            runs["tracer"].append(_process(ours, env))
            runs["mitsuba"].append(_process(theirs, env))
    med = {k: (statistics.median(w for w, _ in v), statistics.median(c for _, c in v)) for k, v in runs.items()}
    for name, (wall, cpu) in med.items():
        spread = [w for w, _ in runs[name]]
        print(f"  {name:<8s} {wall:6.2f} s wall ({min(spread):.2f}-{max(spread):.2f}) {cpu:6.2f} s cpu")
    for i, what in enumerate(("wall", "cpu")):
        ratio = med["tracer"][i] / med["mitsuba"][i]
        ok = figure(f"tracer.cornell_vs_mitsuba_{what}",
                    f"Cornell box {size}x{size} {spp} spp, whole process: tracer / Mitsuba 3 scalar_rgb {what} time",
                    ratio, "x", aim=AIM_MITSUBA)
        print(f"  tracer / Mitsuba {what:<4s} {ratio:5.2f}x (aim at most {AIM_MITSUBA}x) {mark(ok)}")
    print(f"  (load at the end {os.getloadavg()[0]:.2f})")


def validation(args) -> None:
    """The ``--validate`` figures: error of single-tap and --antialias warps against the direct trace, and
    the antialias warp's cost over single-tap's."""
    from lenslab.bench.results import figure, mark
    from lenslab.lenses import Camera
    from lenslab.validate.run import WarpSetting, validate

    from tracer.validate.source import make_source

    quick = bool(args.quick)
    pano, side, ref_spp = ((1024, 512), 128, 16) if quick else ((4096, 2048), 512, 64)
    source = make_source("cornell", None, args.max_depth, noise_free=True)
    view = source.scene.views["default"]
    target = Camera.from_spec("fisheye:fov=180,mapping=equisolid", (side, side), eye=tuple(view.eye),
                              look_at=tuple(view.look_at))
    settings = [WarpSetting.parse("bilinear"), WarpSetting.parse("antialias")]
    val = validate(source, target, [pano], settings, spp=1, reference_spp=ref_spp, seed=None, direct_spp=(),
                   repeat=max(2, min(args.repeat, 5)), with_flip=False, progress=False, keep_images=False)
    rows = {r["setting"]: r for r in val.rows if r["kind"] == "warp"}
    tap, aa = rows["bilinear"], rows["antialias"]
    print(f"validation: Cornell box (noise-free) {pano[0]}x{pano[1]} panorama -> {side}x{side} "
          f"fisheye:fov=180,mapping=equisolid, relative L1 against the direct trace at {ref_spp} spp"
          + (" (--quick: no aims)" if quick else ""))
    tag = "_quick" if quick else ""
    aim_l1, aim_cost = (None, None) if quick else (AIM_VALIDATE_L1, AIM_VALIDATE_COST)
    figure(f"validate.single_tap_l1{tag}", "single-tap bilinear warp vs direct trace, relative L1",
           100.0 * tap["l1"], "%")
    print(f"  single-tap bilinear   {100 * tap['l1']:7.3f}%   warp {tap['warp_seconds'] * 1e3:8.1f} ms")
    ok = figure(f"validate.antialias_l1{tag}", "--antialias warp vs direct trace, relative L1", 100.0 * aa["l1"],
                "%", aim=aim_l1)
    cost = aa["warp_seconds"] / tap["warp_seconds"]
    ok_cost = figure(f"validate.antialias_cost{tag}", "--antialias warp time / single-tap warp time", cost, "x",
                     aim=aim_cost)
    print(f"  --antialias           {100 * aa['l1']:7.3f}%   warp {aa['warp_seconds'] * 1e3:8.1f} ms = {cost:5.2f}x "
          "single-tap" + ("" if quick else f"   aims <= {AIM_VALIDATE_L1:g}% {mark(ok)}, <= {AIM_VALIDATE_COST:g}x "
                                           f"{mark(ok_cost)}"))
