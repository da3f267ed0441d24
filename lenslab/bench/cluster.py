"""Cluster benchmark: a batch of frames and one traced panorama on Dask workers against one local job.

Warp: 32 frames of 2048x1024 EXR (``--quick``: 16 of 1024x512) into a 1024x1024 equisolid fisheye,

  one job        the frames one after the other in this process, one thread (the baseline)
  local default  lenslab warp without a scheduler: one frame per core at once, on threads of this process
  2 workers      one task per frame on a LocalCluster of two single-threaded worker processes (started
                 with lenslab's worker settings, :data:`lenslab.cluster.connect.WORKER_CONFIG`)

with the speed-up and efficiency of the two workers against one job (aim: 1.7x), and the overhead of a
task: the workers' busy time taken from their wall time, per task (aim: under 20 ms). The warp's map
is made once per worker; its cost is set beside the cost of scattering the map's bytes to the workers.
Convert: the same frames to EXR with ``--jobs 1``, ``--jobs 2`` and the two workers, with the workers' CPU
time over ``--jobs 1``'s. Every warp and convert configuration runs once per round, ``--repeat`` rounds,
in the reverse order every other round; the medians count.

Trace: ``tracer render --scheduler`` of a 2048x1024 panorama of the Cornell box at 64 spp (``--quick``:
4 spp) on one worker and on two, interleaved, the speed-up against one worker (aim: 1.7x), and the two
workers' CPU time over the one worker's (1.0: cutting the image into tiles adds no work). Each cluster is
started, and its workers have loaded the scene, before the clock starts; every figure's machine load is
in the JSON record.
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar

from lenslab.jobs.job import Job

AIM_SPEEDUP = 1.7  # two workers against one job, on two cores
AIM_OVERHEAD_MS = 20.0  # scheduling cost of one task


def add_arguments(parser: argparse.ArgumentParser) -> None:
    from lenslab.jobs.arguments import positive_int

    parser.add_argument("--quick", action="store_true",
                        help="16 frames of 1024x512, and the panorama at 4 spp (a few minutes)")
    parser.add_argument("--frames", type=positive_int, default=None, help="number of frames (default 32; 16 with --quick)")
    parser.add_argument("--skip-trace", action="store_true", help="the warp and convert batches only")
    parser.add_argument("--repeat", type=positive_int, default=3,
                        help="runs of each warp and convert batch and of each trace, interleaved; the medians "
                             "count (default 3)")


def make_frames(folder: Path, n: int, width: int, height: int) -> list[Path]:
    """``n`` smooth HDR frames (a sky gradient, a sun and a drifting pattern) as half EXR files."""
    import numpy as np

    from lenslab.io import write

    y, x = np.mgrid[0:height, 0:width].astype(np.float32)
    sky = (1.5 - y / height)[..., None] * np.array([0.4, 0.6, 1.0], np.float32)
    paths = []
    for i in range(n):
        image = sky + 0.2 * (1 + np.sin((x + 37 * i) / 23.0) * np.cos(y / 17.0))[..., None]
        image[(x - width * (0.3 + 0.01 * i)) ** 2 + (y - height * 0.3) ** 2 < (height / 40) ** 2] = 5000.0
        path = folder / f"frame{i:04d}.exr"
        write(path, image.astype(np.float32))
        paths.append(path)
    return paths


def warp_job():
    """The warp of the batch benchmarks, as ``lenslab warp --to fisheye:fov=180,mapping=equisolid --size
    1024x1024 --overwrite`` makes it."""
    from lenslab.jobs.warp import WarpJob

    return WarpJob(to="fisheye:fov=180,mapping=equisolid", size=(1024, 1024), quiet=True, overwrite=True)


def _local(job, frames, out: Path, threads: int) -> float:
    from lenslab.cluster.tasks import limit_threads
    from lenslab.jobs.runner import execute

    limit_threads(threads)
    t0 = time.perf_counter()
    for src in frames:
        _, _, error, _ = execute(job, str(src), str(out / (src.stem + ".exr")))
        if error:
            raise RuntimeError(error)
    return time.perf_counter() - t0


def _threads(job, frames, out: Path, jobs: int) -> float:
    """The local default: ``jobs`` frames at once on threads (:mod:`lenslab.cluster.threads`)."""
    from lenslab.cluster.threads import run_threads
    from lenslab.jobs.runner import execute

    t0 = time.perf_counter()
    results = run_threads(lambda src: execute(job, str(src), str(out / (src.stem + ".exr"))), frames, jobs)
    seconds = time.perf_counter() - t0
    if any(r[2] for r in results):
        raise RuntimeError(next(r[2] for r in results if r[2]))
    return seconds


def _on_cluster(client, job, frames, out: Path) -> tuple[float, float, float]:
    """Wall time of the batch, the workers' summed busy time and their processes' CPU time."""
    from lenslab.jobs.runner import run_on_cluster

    workers: dict = {}
    pairs = [(str(src), str(out / (src.stem + ".exr"))) for src in frames]
    cpu = _workers_cpu(client)
    t0 = time.perf_counter()
    results = run_on_cluster(client, job, pairs, workers=workers, close=False)
    wall = time.perf_counter() - t0
    cpu = _workers_cpu(client) - cpu
    errors = [r[2] for r in results if r[2]]
    if errors:
        raise RuntimeError(errors[0])
    return wall, sum(s for _, s in workers.values()), cpu


def warm_up(client, job, frame: Path, out: Path) -> None:
    """One frame on every worker, so that each has loaded its kernels and made its map before timing."""
    from lenslab.cluster.run import submit
    from lenslab.jobs.runner import execute

    futures = [submit(client, execute, job, str(frame), str(out / f"warm-{i}.exr"), name="warm-up", workers=[w])
               for i, w in enumerate(sorted(client.nthreads()))]
    for future in futures:
        future.result()


def _fresh(folder: Path) -> Path:
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    return folder


def batches(args, tmp: Path) -> None:
    from lenslab.bench.results import figure, mark
    from lenslab.cluster.connect import local_cluster
    from lenslab.jobs.convert import ConvertJob

    n = args.frames or (16 if args.quick else 32)
    width, height = (1024, 512) if args.quick else (2048, 1024)
    frames = make_frames(_fresh(tmp / "in"), n, width, height)
    job = warp_job()
    _local(job, frames[:1], _fresh(tmp / "out"), 1)  # compile or load the kernels first
    cores = os.cpu_count() or 1
    convert = ConvertJob(to="exr", overwrite=True, pixel_type="half", compression="zip")
    runs: dict[str, list] = {k: [] for k in ("one", "one_cpu", "default", "cluster", "c_one", "c_one_cpu", "c_two",
                                             "c_cluster")}
    with local_cluster(workers=2) as client:
        warm_up(client, job, frames[0], _fresh(tmp / "out"))
        warm_up(client, convert, frames[0], _fresh(tmp / "out"))
        # interleaved, so that every configuration sees the same load, and in the reverse order every other
        # round, so that none always runs first (after the previous batch's outputs were written)
        steps = [("one", lambda: _timed(_local, job, frames, _fresh(tmp / "out"), 1)),
                 ("default", lambda: _threads(job, frames, _fresh(tmp / "out"), cores)),
                 ("cluster", lambda: _on_cluster(client, job, frames, _fresh(tmp / "out"))),
                 ("c_one", lambda: _timed(convert_jobs, frames, tmp, convert, 1)),
                 ("c_two", lambda: convert_jobs(frames, tmp, convert, 2)),
                 ("c_cluster", lambda: _on_cluster(client, convert, frames, _fresh(tmp / "out")))]
        for r in range(max(1, args.repeat)):
            for key, step in steps if r % 2 == 0 else steps[::-1]:
                value = step()
                if key in ("one", "c_one"):  # (wall, CPU time of this thread: the one job runs in it)
                    runs[key + "_cpu"].append(value[1])
                    value = value[0]
                runs[key].append(value)
        one, default = statistics.median(runs["one"]), statistics.median(runs["default"])
        wall, busy, cpu = sorted(runs["cluster"])[len(runs["cluster"]) // 2]
        one_cpu = statistics.median(runs["one_cpu"])
        map_build, scatter = map_costs(client, job, frames[0])
        noop = noop_overhead(client)
    print(f"warp: {n} frames {width}x{height} -> fisheye 1024x1024, medians of {max(1, args.repeat)} runs "
          f"(load {os.getloadavg()[0]:.2f})")
    print(f"  one job, one thread        {one:8.2f} s   baseline")
    print(f"  local, {cores} frames at once    {default:8.2f} s   {one / default:5.2f}x")
    speedup = one / wall
    ok = figure("cluster.warp_two_workers_speedup", f"warp {n} frames: two Dask workers vs one job", speedup, "x",
                aim=AIM_SPEEDUP, better="higher")
    print(f"  two Dask workers           {wall:8.2f} s   {speedup:5.2f}x (aim {AIM_SPEEDUP}x) {mark(ok)}; "
          f"efficiency {speedup / 2:.0%}")
    figure("cluster.warp_local_threads_speedup", f"warp {n} frames: local default ({cores} frames at once) vs one job",
           one / default, "x")
    figure("cluster.warp_two_workers_efficiency", "warp: two workers' efficiency against one job", speedup / 2, "",
           better="higher")
    figure("cluster.warp_workers_cpu_ratio", "warp: the two workers' CPU time over the one job's (1: the cluster "
           "adds no work)", cpu / one_cpu, "")
    print(f"  CPU time: one job {one_cpu:.2f} s, the two workers {cpu:.2f} s ({cpu / one_cpu:.2f}x)")
    overhead = max(0.0, (2 * wall - busy) / n) * 1e3
    figure("cluster.warp_idle_per_task_ms", "warp batch: workers' time outside the tasks, per task", overhead, "ms")
    print(f"  workers' idle time, per task {overhead:6.1f} ms  (wall clock x 2 workers - time in the tasks)")
    ok = figure("cluster.task_overhead_ms", "overhead of a task (empty tasks, same path)", noop, "ms",
                aim=AIM_OVERHEAD_MS)
    print(f"  overhead of a task         {noop:8.1f} ms  (empty tasks through the same path; aim under "
          f"{AIM_OVERHEAD_MS:g} ms) {mark(ok)}")
    figure("cluster.map_build_ms", "warp map made on a worker", map_build * 1e3, "ms")
    figure("cluster.map_scatter_ms", "warp map made once and scattered to two workers", (map_build + scatter) * 1e3,
           "ms")
    # made on every worker at once, the map costs its build time of wall clock; scattered, it is built once
    # and then shipped: build time plus scatter time (less CPU in all, more wall clock)
    print(f"  the map made on a worker   {map_build * 1e3:8.1f} ms of wall clock (every worker at once); made once "
          f"and scattered {(map_build + scatter) * 1e3:.1f} ms ({scatter * 1e3:.1f} ms of it to ship the bytes)")
    c_one, c_two = statistics.median(runs["c_one"]), statistics.median(runs["c_two"])
    c_wall, _, c_cpu = sorted(runs["c_cluster"])[len(runs["c_cluster"]) // 2]
    c_one_cpu = statistics.median(runs["c_one_cpu"])
    print(f"convert: {n} frames to EXR, medians of {max(1, args.repeat)} runs: --jobs 1 {c_one:.2f} s, --jobs 2 "
          f"{c_two:.2f} s ({c_one / c_two:.2f}x), two Dask workers {c_wall:.2f} s ({c_one / c_wall:.2f}x); CPU time: "
          f"--jobs 1 {c_one_cpu:.2f} s, the two workers {c_cpu:.2f} s ({c_cpu / c_one_cpu:.2f}x)")
    figure("cluster.convert_jobs2_speedup", f"convert {n} frames: --jobs 2 vs --jobs 1", c_one / c_two, "x")
    figure("cluster.convert_two_workers_speedup", f"convert {n} frames: two Dask workers vs --jobs 1",
           c_one / c_wall, "x", aim=AIM_SPEEDUP, better="higher")
    figure("cluster.convert_workers_cpu_ratio", "convert: the two workers' CPU time over --jobs 1's (1: the "
           "cluster adds no work)", c_cpu / c_one_cpu, "")


def _timed(fn, *args) -> tuple[float, float]:
    """``fn(*args)`` (which returns its wall time) and the CPU time this thread spent in it."""
    cpu = time.thread_time()
    wall = fn(*args)
    return wall, time.thread_time() - cpu


@dataclass(frozen=True)
class EmptyJob(Job):
    """A job that does nothing, for the overhead of the path every file takes."""

    command: ClassVar[str] = "empty"

    def run(self, src: str, dst: str, progress=None) -> None:
        return None


def noop_overhead(client, n: int = 200) -> float:
    """Milliseconds of a worker's time per task, for ``n`` empty tasks through the runner's cluster path."""
    from lenslab.jobs.runner import run_on_cluster

    workers = max(1, sum(client.nthreads().values()))
    with tempfile.TemporaryDirectory() as folder:
        t0 = time.perf_counter()
        run_on_cluster(client, EmptyJob(), [(str(i), os.path.join(folder, str(i))) for i in range(n)], close=False)
    return (time.perf_counter() - t0) * workers / n * 1e3


def convert_jobs(frames, tmp: Path, job, jobs: int) -> float:
    from lenslab.jobs.runner import run_local

    out = _fresh(tmp / "out")
    pairs = [(str(src), out / (src.stem + ".exr")) for src in frames]
    t0 = time.perf_counter()
    results = run_local(job, pairs, jobs=jobs)
    seconds = time.perf_counter() - t0
    if any(r[2] for r in results):
        raise RuntimeError(next(r[2] for r in results if r[2]))
    return seconds


def map_costs(client, job, frame: Path) -> tuple[float, float]:
    """Seconds to make the warp's map on a worker (the first frame's extra time over a later one) and to
    scatter an array of the map's size to both workers."""
    import numpy as np

    from lenslab.cluster.run import submit
    from dataclasses import replace

    from lenslab.jobs.runner import execute
    from lenslab.warp.batch import map_bytes_estimate

    t = []
    moved = replace(job, overwrite=True, yaw=0.5)  # a geometry no worker has seen yet
    worker = sorted(client.nthreads())[0]
    for i in range(2):  # on one worker, the first frame makes the map, the second reuses it
        out = str(frame.with_name(f"map-{i}.exr"))
        t.append(submit(client, execute, moved, str(frame), out, name="map", workers=[worker]).result()[2])
    build = max(0.0, t[0] - t[1])
    from lenslab.lenses import Camera

    dst = Camera.from_spec("fisheye:fov=180,mapping=equisolid", (1024, 1024))
    payload = np.zeros(map_bytes_estimate(dst, 1, False) // 4, dtype=np.float32)
    t0 = time.perf_counter()
    future = client.scatter(payload, broadcast=True)
    client.replicate([future])
    scatter = time.perf_counter() - t0
    client.cancel([future])
    return build, scatter


def _workers_cpu(client) -> float:
    """Seconds of CPU the cluster's worker processes have used so far (all their threads)."""
    return sum(user + system for user, system in client.run(_cpu_times).values())


def _cpu_times() -> tuple[float, float]:
    t = os.times()
    return t.user, t.system


def trace(args, tmp: Path) -> None:
    """One worker against two, interleaved (one worker, two, one, two, ...: on a shared machine a single
    pair of runs measures the change of load between them as much as the scaling), medians of
    ``--repeat`` runs each; with the workers' CPU time, which the load of other processes hardly moves."""
    from lenslab.bench.results import figure, mark
    from lenslab.cluster.connect import local_cluster

    size, spp = "2048x1024", (4 if args.quick else 64)
    exe = [shutil.which("tracer")] if shutil.which("tracer") else [sys.executable, "-m", "tracer.cli"]
    command = exe + ["render", "--scene", "cornell", "--camera", "equirect", "--seed", "1", "-q", "--overwrite"]
    runs: dict[int, list] = {1: [], 2: []}
    for _ in range(max(1, args.repeat)):
        for workers in (1, 2):
            with local_cluster(workers=workers) as client:
                address = client.scheduler.address
                out = str(tmp / f"trace-{workers}.exr")
                subprocess.run(command + ["--size", "64x32", "--spp", "1", "-o", out, "--scheduler", address],
                               check=True)  # the workers load the scene and build its embree structure
                cpu = _workers_cpu(client)
                t0 = time.perf_counter()
                subprocess.run(command + ["--size", size, "--spp", str(spp), "-o", out, "--scheduler", address],
                               check=True)
                runs[workers].append((time.perf_counter() - t0, _workers_cpu(client) - cpu))
    one, two = (statistics.median(w for w, _ in runs[n]) for n in (1, 2))
    cpu_one, cpu_two = (statistics.median(c for _, c in runs[n]) for n in (1, 2))
    speedup = one / two
    ok = figure("cluster.trace_two_workers_speedup", f"trace {size} at {spp} spp: two workers vs one", speedup, "x",
                aim=AIM_SPEEDUP, better="higher")
    figure("cluster.trace_workers_cpu_ratio", f"trace {size} at {spp} spp: the two workers' CPU time over the one "
           "worker's (1: splitting adds no work)", cpu_two / cpu_one, "")
    print(f"trace: cornell panorama {size} at {spp} spp, medians of {max(1, args.repeat)} runs, interleaved (load "
          f"{os.getloadavg()[0]:.2f}): one worker {one:.2f} s, two workers {two:.2f} s, {speedup:.2f}x (aim "
          f"{AIM_SPEEDUP}x) {mark(ok)}; the workers' CPU {cpu_one:.2f} s and {cpu_two:.2f} s "
          f"({cpu_two / cpu_one:.2f}x)")


def run(args: argparse.Namespace) -> int:
    with tempfile.TemporaryDirectory(prefix="lenslab-bench-cluster-") as tmp:
        batches(args, Path(tmp))
        if not args.skip_trace:
            trace(args, Path(tmp))
    return 0
