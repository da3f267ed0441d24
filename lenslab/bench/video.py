"""Video benchmark: an H.264 equirect clip into an H.264 180-degree fisheye, whole process, ``lenslab warp``
against ffmpeg's v360 filter on the same clip.

The clips are made first by ffmpeg (``testsrc2``, H.264 4:2:0, 24 frames/s) at 1024x512, 1920x1080 and
3840x1920; each goes into a square fisheye as tall as the source (512, 1080, 1920 px). Both sides decode
H.264, resample bilinearly (v360's ``line``, lenslab's default) and encode with libx264 at its defaults
(preset medium, CRF 23, frame threads: ``threads=3 sliced_threads=0`` on two cores), each on every thread it
wants; the settings each encoder wrote into its output (x264's own options SEI) are printed, so a run shows
that the comparison is fair (Debian's ffmpeg and PyAV bring their own builds of x264). Every command runs as its own process,
``--repeat`` times, interleaved with the other, after one uncounted lenslab run (its kernels compiled or
loaded from numba's cache, Python's bytecode written: as in ``lenslab bench startup``, the runs may write that
cache even where this shell forbids it, since an installed lenslab has its bytecode, and a run that compiles every
module from source measures the shell, not the command); the figures are the median wall times as ratios
lenslab / ffmpeg, aim at most 1x, with CPU time (user + system of the process) beside them.

ffmpeg must be on PATH (Debian's ffmpeg is enough); without it the benchmark says so and ends with 1.
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

AIM = 1.0  # lenslab / ffmpeg wall time, all threads both
SIZES = ((1024, 512), (1920, 1080), (3840, 1920))


def add_arguments(parser: argparse.ArgumentParser) -> None:
    from lenslab.jobs.arguments import positive_int

    parser.add_argument("--frames", type=positive_int, default=48, help="frames per clip (default 48)")
    parser.add_argument("--repeat", type=positive_int, default=3, help="runs of each command; medians count (default 3)")
    parser.add_argument("--sizes", default=",".join(f"{w}x{h}" for w, h in SIZES),
                        help="source sizes WxH, comma-separated (default: 1024x512,1920x1080,3840x1920)")


def make_clip(path: Path, width: int, height: int, frames: int) -> None:
    """An H.264 clip of ``frames`` frames of ffmpeg's test pattern at 24 frames/s."""
    cmd = ["ffmpeg", "-v", "error", "-y", "-f", "lavfi", "-i", f"testsrc2=size={width}x{height}:rate=24",
           "-frames:v", str(frames), "-c:v", "libx264", "-pix_fmt", "yuv420p", str(path)]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)


def _ffmpeg_cmd(clip: Path, out: Path, side: int) -> list[str]:
    v360 = f"v360=input=e:output=fisheye:h_fov=180:v_fov=180:w={side}:h={side}:interp=line"
    return ["ffmpeg", "-v", "error", "-y", "-i", str(clip), "-vf", v360, "-c:v", "libx264", "-pix_fmt", "yuv420p",
            str(out)]


def _lenslab_cmd(clip: Path, out: Path, side: int) -> list[str]:
    return [sys.executable, "-m", "lenslab", "warp", str(clip), "-o", str(out), "--to", "fisheye:fov=180",
            "--from", "equirect", "--size", f"{side}x{side}", "--overwrite", "-q"]


def x264_settings(path: Path) -> str:
    """The x264 build and the options that set its speed, as the encoder wrote them into ``path``."""
    import re

    head = path.read_bytes()[:1 << 16].decode("latin-1")
    core = re.search(r"x264 - core (\d+)", head)
    keys = ("threads", "sliced_threads", "crf", "subme", "ref", "rc_lookahead", "bframes")
    found = {k: re.search(rf"\b{k}=([\d.]+)", head) for k in keys}
    if core is None:
        return "not x264"
    return f"x264 core {core.group(1)}: " + " ".join(f"{k}={m.group(1)}" for k, m in found.items() if m)


def run(args: argparse.Namespace) -> int:
    from lenslab.bench.batch import timed_run
    from lenslab.bench.results import figure, mark

    if not shutil.which("ffmpeg"):
        print("lenslab bench video: ffmpeg is not on PATH; it is the baseline of this benchmark", file=sys.stderr)
        return 1
    try:
        sizes = [tuple(int(v) for v in s.lower().split("x")) for s in args.sizes.split(",") if s.strip()]
    except ValueError:
        print(f"lenslab bench video: --sizes {args.sizes!r}: give WxH,WxH,...", file=sys.stderr)
        return 2
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}  # a warm install (above)
    print(f"video: H.264 equirect clips of {args.frames} frames -> H.264 180-degree fisheye as tall as the source, "
          f"whole process, all threads both, {args.repeat} runs each, medians (load {os.getloadavg()[0]:.2f})")
    with tempfile.TemporaryDirectory(prefix="lenslab-bench-video-") as tmp:
        for width, height in sizes:
            clip = Path(tmp) / f"clip{width}x{height}.mp4"
            make_clip(clip, width, height, args.frames)
            side = height
            out_f, out_l = Path(tmp) / "ffmpeg.mp4", Path(tmp) / "lenslab.mp4"
            timed_run(_lenslab_cmd(clip, out_l, side), env, False)  # kernels compiled or loaded: not counted
            runs: dict[str, list[tuple[float, float]]] = {"ffmpeg": [], "lenslab": []}
            for _ in range(args.repeat):  # interleaved, so both see the same load
                runs["ffmpeg"].append(timed_run(_ffmpeg_cmd(clip, out_f, side), env, False))
                runs["lenslab"].append(timed_run(_lenslab_cmd(clip, out_l, side), env, False))
            if (width, height) == sizes[0]:
                print(f"  encoders: ffmpeg {x264_settings(out_f)}\n            lenslab {x264_settings(out_l)}")
            med = {k: (statistics.median(w for w, _ in v), statistics.median(c for _, c in v)) for k, v in runs.items()}
            wall, cpu = med["lenslab"][0] / med["ffmpeg"][0], med["lenslab"][1] / med["ffmpeg"][1]
            ok = figure(f"video.{width}x{height}_wall", f"H.264 {width}x{height} clip, {args.frames} frames -> "
                        f"{side}x{side} fisheye: lenslab warp / ffmpeg v360 wall, all threads", wall, "x", aim=AIM)
            figure(f"video.{width}x{height}_cpu", f"the same, CPU time (user + system)", cpu, "x", detail=True)
            print(f"  {width}x{height} -> {side}x{side}: ffmpeg {med['ffmpeg'][0]:6.2f} s wall {med['ffmpeg'][1]:6.2f} "
                  f"s cpu   lenslab {med['lenslab'][0]:6.2f} s wall {med['lenslab'][1]:6.2f} s cpu   "
                  f"{wall:5.2f}x wall (aim at most {AIM:g}x) {mark(ok)}, {cpu:5.2f}x cpu", flush=True)
    print(f"  (load at the end {os.getloadavg()[0]:.2f})")
    return 0
