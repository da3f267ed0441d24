"""Benchmarks. Each prints its figures as ratios against a baseline measured in the same run,
because machines are shared and noisy.

  lenslab bench io       read/write throughput per format against numpy.fromfile/tofile
  lenslab bench lenses   directions per second per lens model against plain NumPy equirect
  lenslab bench startup  whole-command wall time on a 256 x 128 image against python -c "import numpy"
  lenslab bench tone     megapixels per second per curve against numpy.clip
  lenslab bench warp     equirect -> fisheye warps against cv2.remap with precomputed maps
  lenslab bench batch    8 EXR frames into a fisheye, whole process, against ffmpeg's v360
  lenslab bench video    H.264 clips (1024x512 to 3840x1920) into a fisheye, whole process, against ffmpeg's v360
  lenslab bench cluster  32 frames and a traced panorama on two Dask workers against one local job
  lenslab bench memory   peak memory of commands on hostile files and on large valid images
"""

from __future__ import annotations

import argparse
import importlib

TARGETS = {
    "io": "read/write throughput per format, and convert throughput",
    "lenses": "pixel_to_dir and dir_to_pixel throughput per lens model",
    "startup": "wall time of convert, tonemap and warp on a small image",
    "tone": "tone curve throughput per curve",
    "warp": "warp throughput and peak memory",
    "batch": "8 EXR frames into a fisheye, whole process, against ffmpeg's v360",
    "video": "H.264 clips into an H.264 fisheye, whole process, against ffmpeg's v360",
    "cluster": "a batch of frames and a traced panorama on Dask workers against one local job",
    "memory": "peak memory of commands on hostile files and on large valid images",
}


def plain(doc: str) -> str:
    """A module docstring as ``--help`` text: reStructuredText's literals and roles as plain words."""
    import re

    text = re.sub(r":[a-z]+:`~?([^`]+)`", lambda m: m.group(1).rsplit(".", 1)[-1] if "~" in m.group(0)
                  else m.group(1), doc)
    return re.sub(r"``([^`]+)``", r"\1", text).strip()


def add_arguments(parser: argparse.ArgumentParser) -> None:
    sub = parser.add_subparsers(dest="target", metavar="TARGET", required=True)
    for name, help_text in TARGETS.items():
        try:
            module = importlib.import_module(f"lenslab.bench.{name}")
        except ModuleNotFoundError as exc:
            if exc.name != f"lenslab.bench.{name}":
                raise
            continue
        p = sub.add_parser(name, help=help_text, description=plain(module.__doc__ or help_text))
        module.add_arguments(p)
        p.add_argument("--json", metavar="FILE", default=None,
                       help="also write every figure, its aim and whether it is met, as JSON to FILE "
                            "(tools/speed_table.py builds the speed table of docs/speed.md from such files)")
        p.add_argument("--overwrite", action="store_true", help="replace an existing --json FILE")
        p.set_defaults(_bench=module, _bench_name=name)


def run(args: argparse.Namespace) -> int:
    import sys

    from lenslab.bench import results

    if getattr(args, "json", None):  # refused before the benchmark runs, not after
        from lenslab.jobs.policy import check_output

        check_output(args.json, (), args.overwrite)
    record = results.start()
    status = int(args._bench.run(args) or 0)
    if getattr(args, "json", None):
        results.write(args.json, args._bench_name, record, argv=sys.argv[1:], overwrite=args.overwrite)
        print(f"figures written to {args.json}")
    return status
