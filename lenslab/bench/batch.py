"""Batch benchmark: 8 frames of 2048x1024 EXR into a 1024x1024 180-degree fisheye, whole process,
``lenslab warp`` against ffmpeg's v360 filter on the same frames.

Both write half-float EXR with ZIP compression, read the same files and resample bilinearly (v360's
default ``line`` interpolation, lenslab's default ``bilinear``). Each command runs as its own process,
``--repeat`` times, interleaved; the figures are medians of wall time and of CPU time (user + system of
the child processes), as ratios lenslab / ffmpeg (lower is better):

  one thread each   ffmpeg ``-threads 1 -filter_threads 1``; lenslab with ``NUMBA_NUM_THREADS=1``; both
                    pinned to one core with ``taskset`` when it exists, so the codecs' own threads count
                    too (aim: at most 0.7x)
  all threads       both with their defaults on every core (aim: under 1.0x, ahead of ffmpeg)

ffmpeg 5.1's v360 takes no float frames: ffmpeg converts each EXR frame to 16-bit integers for it and
back (two swscale passes inside ffmpeg's time, values above 1 clipped), so its output is not HDR; lenslab
keeps the floats. ``tests/bench/test_bench_batch.py`` checks that both commands make the same fisheye.

ffmpeg must be on PATH (Debian's ffmpeg is enough); without it the benchmark says so and ends with 1.
"""

from __future__ import annotations

import argparse
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

AIM_ONE_THREAD = 0.7  # lenslab / ffmpeg, one thread each
AIM_ALL_THREADS = 1.0  # ahead of ffmpeg with every thread


def add_arguments(parser: argparse.ArgumentParser) -> None:
    from lenslab.jobs.arguments import image_size, positive_int

    parser.add_argument("--frames", type=positive_int, default=8, help="number of frames (default 8)")
    parser.add_argument("--size", type=image_size, default=(2048, 1024), metavar="WxH",
                        help="frame size (default 2048x1024)")
    parser.add_argument("--out-size", type=positive_int, default=1024, help="fisheye side in pixels (default 1024)")
    parser.add_argument("--repeat", type=positive_int, default=3, help="runs of each command; medians count (default 3)")


def _ffmpeg_cmd(inputs: Path, out: Path, side: int, one: bool) -> list[str]:
    threads = ["-threads", "1", "-filter_threads", "1"] if one else []
    v360 = f"v360=input=e:output=fisheye:h_fov=180:v_fov=180:w={side}:h={side}:interp=line"
    return (["ffmpeg", "-v", "error", "-y", *threads, "-i", str(inputs / "frame%04d.exr"), "-vf", v360,
             *(["-threads", "1"] if one else []), "-c:v", "exr", "-format", "half", "-compression", "zip16",
             str(out / "frame%04d.exr")])


def _lenslab_cmd(inputs: Path, out: Path, side: int) -> list[str]:
    return [sys.executable, "-m", "lenslab", "warp", str(inputs), "-o", str(out), "--to", "fisheye:fov=180",
            "--size", f"{side}x{side}", "--filter", "bilinear", "--overwrite", "-q"]


def timed_run(cmd: list[str], env: dict, one: bool) -> tuple[float, float]:
    """Wall seconds and CPU seconds (children's user + system) of one whole process."""
    if one and shutil.which("taskset"):
        cmd = ["taskset", "-c", str(min(os.sched_getaffinity(0))), *cmd]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    done = subprocess.run(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode:
        raise RuntimeError(f"{' '.join(cmd[:3])}... failed: {done.stderr.strip()[-400:]}")
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def run(args) -> int:
    from lenslab.bench.cluster import make_frames
    from lenslab.bench.results import figure, mark

    if not shutil.which("ffmpeg"):
        print("lenslab bench batch: ffmpeg is not on PATH; it is the baseline of this benchmark", file=sys.stderr)
        return 1
    width, height = args.size
    side = args.out_size
    with tempfile.TemporaryDirectory(prefix="lenslab-bench-batch-") as tmp:
        inputs = Path(tmp) / "in"
        inputs.mkdir()
        make_frames(inputs, args.frames, width, height)
        out_f, out_l = Path(tmp) / "ffmpeg", Path(tmp) / "lenslab"
        out_f.mkdir()
        env_all = dict(os.environ)
        env_one = {**env_all, "NUMBA_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "OPENCV_FOR_THREADS_NUM": "1"}
        # the kernels are compiled (or loaded from numba's cache) once before the clock starts
        timed_run(_lenslab_cmd(inputs, out_l, side), env_all, False)
        print(f"batch: {args.frames} frames {width}x{height} EXR -> {side}x{side} 180-degree fisheye, whole process, "
              f"{args.repeat} runs each, medians (load {os.getloadavg()[0]:.2f})")
        for one, key, aim in ((True, "one_thread", AIM_ONE_THREAD), (False, "all_threads", AIM_ALL_THREADS)):
            env = env_one if one else env_all
            runs: dict[str, list[tuple[float, float]]] = {"ffmpeg": [], "lenslab": []}
            for _ in range(args.repeat):  # interleaved, so both see the same load
                runs["ffmpeg"].append(timed_run(_ffmpeg_cmd(inputs, out_f, side, one), env, one))
                runs["lenslab"].append(timed_run(_lenslab_cmd(inputs, out_l, side), env, one))
            med = {k: (statistics.median(w for w, _ in v), statistics.median(c for _, c in v)) for k, v in runs.items()}
            wall, cpu = med["lenslab"][0] / med["ffmpeg"][0], med["lenslab"][1] / med["ffmpeg"][1]
            label = "one thread each" if one else f"all threads ({len(os.sched_getaffinity(0))} cores)"
            ok = figure(f"batch.{key}_wall", f"batch of {args.frames} frames, {label}: lenslab warp / ffmpeg v360 wall",
                        wall, "x", aim=aim)
            figure(f"batch.{key}_cpu", f"batch of {args.frames} frames, {label}: lenslab warp / ffmpeg v360 CPU", cpu,
                   "x", note="user + system time of the whole process")
            print(f"  {label:<22s} ffmpeg {med['ffmpeg'][0]:6.2f} s wall {med['ffmpeg'][1]:6.2f} s cpu   "
                  f"lenslab {med['lenslab'][0]:6.2f} s wall {med['lenslab'][1]:6.2f} s cpu")
            print(f"  {'':<22s} lenslab / ffmpeg: {wall:5.2f}x wall (aim at most {aim:g}x) {mark(ok)}, "
                  f"{cpu:5.2f}x cpu")
        print(f"  (load at the end {os.getloadavg()[0]:.2f})")
    return 0
