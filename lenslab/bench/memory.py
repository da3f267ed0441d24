"""Memory: the peak resident memory of whole commands, each in its own process (``getrusage`` of the
child: peak RSS), on hostile files and on large valid ones.

Aims:

- no file of the hostile corpus, each refused, makes its command allocate more than 200 MB: every file
  (``lenslab.bench.hostile``: headers declaring 20000 x 20000 pixels in a few hundred bytes, page loops,
  alias bombs, deep nesting...) goes through the command that must refuse it; the figure is its peak
  beyond the baseline, the peak of ``lenslab info --formats`` (the interpreter and the modules every
  command loads), measured in the same run;
- the files the input budget admits at its edges (:func:`edge_at_budget`) go through convert, warp and
  tonemap: the largest image any file may decode to (96 MiB of float32) against the same 200 MB; the
  largest a file of 0.5 or 1 MiB may decode to (512 times its bytes: 268 and 537 MB), which the budget
  admits as an image of that size, against a valid image's aim (below: 1.5 times the decoded image plus
  200 MB), with each figure's multiple of the decoded image beside it;
- reading, converting and warping a valid SIDE x SIDE image (8192 by default) as Radiance ``.hdr``
  (run-length encoded), float TIFF, EXR and 16-bit PNG peak at most 1.5 times the decoded float image
  (SIDE * SIDE * 3 * 4 bytes) plus 200 MB. Read: ``lenslab.io.read``; convert: to EXR; warp: into a
  1024 x 1024 fisheye, the source taken as a 90-degree perspective view. The test images are a
  smooth gradient with noise (files of realistic size), written by a child process before they are
  measured;
- a warp whose output is much larger than its source (``memory.enlarge_*``: a 1024 x 512 panorama made in the
  bench, warped into an 8192 x 4096 equirect as EXR and PNG, what a user who enlarges a panorama or sends a
  photo into one asks) peaks at most 1.5 times the output's float32 RGBA image (537 MB) plus the source's
  decoded image plus 200 MB beyond the baseline: the output once, its alpha while it joins the colour, a
  bounded working set (OpenCV's modules, a band's scratch) and no second copy of the output; the same aim for
  an RGBA panorama (``memory.enlarge_rgba_exr``: its alpha warped as the output's, no coverage plane beside it)
  and for the panorama warped through an ST map of the output's size (``memory.enlarge_stmap_exr``: the map held
  as its s and t, half the output, within the aim's half).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

AIM_HOSTILE_MB = 200.0
AIM_FACTOR, AIM_EXTRA_MB = 1.5, 200.0
FORMATS = {"hdr": ("big.hdr", {}), "tiff": ("big.tif", {}), "exr": ("big.exr", {"pixel_type": "half"}),
           "png16": ("big.png", {"bits": 16})}

MAKE = """
import sys, numpy as np, lenslab.io as lio
size, path, opts = sys.argv[1].split("x"), sys.argv[2], eval(sys.argv[3])  # SIDE or WIDTHxHEIGHT
y = np.linspace(0.0, 4.0, int(size[-1]), dtype=np.float32)[:, None, None]
x = np.linspace(0.0, 1.0, int(size[0]), dtype=np.float32)[None, :, None]
img = y * (0.5 + x) * np.array([1.0, 0.8, 0.6], np.float32)
img += np.random.default_rng(0).random(img.shape, dtype=np.float32) * 0.01
if opts.pop("alpha", False):  # premultiplied by an alpha that falls from 1 to 0 across the image
    a = np.broadcast_to(1.0 - x, img.shape[:2] + (1,)).astype(np.float32)
    img = np.concatenate([img * a, a], axis=2)
lio.write(path, img, **opts)
"""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    from lenslab.jobs.arguments import positive_int

    parser.add_argument("--side", type=positive_int, default=8192, help="side of the large valid images (default 8192)")
    parser.add_argument("--no-valid", dest="valid", action="store_false",
                        help="measure the hostile corpus only (no large images)")
    parser.add_argument("--enlarging-only", dest="enlarging_only", action="store_true",
                        help="measure the warps into outputs larger than their source only")


#: runs ``argv[2:]`` as its child and writes the child's peak RSS (KiB) into the file ``argv[1]``; exits as
#: the child did. A process's peak RSS (``getrusage``) starts at the RSS of the process that forked it
#: (Linux counts the memory it shares at the fork, and at ``exec`` the memory it leaves): a command forked
#: straight from a big process (a benchmark that made its test files, a test runner) would show that
#: process's size. Forked from this small interpreter (``-S``: a few MB), it shows its own.
LAUNCHER = """import os, signal, sys
pid = os.fork()
if pid == 0:
    os.execvp(sys.argv[2], sys.argv[2:])
_, status, usage = os.wait4(pid, 0)
with open(sys.argv[1], "w") as f:
    f.write(str(usage.ru_maxrss))
if os.WIFSIGNALED(status):
    signal.signal(os.WTERMSIG(status), signal.SIG_DFL)
    os.kill(os.getpid(), os.WTERMSIG(status))
sys.exit(os.waitstatus_to_exitcode(status))
"""


def launched(argv: list[str], peak_file) -> list[str]:
    """``argv`` run through :data:`LAUNCHER`, which writes its peak RSS in KiB into ``peak_file``."""
    return [sys.executable, "-S", "-c", LAUNCHER, str(peak_file), *argv]


def read_peak_mb(peak_file) -> float:
    """The peak RSS :data:`LAUNCHER` wrote, in MB (nan when the launcher itself was killed)."""
    try:
        return int(Path(peak_file).read_text()) / 1024 * 1.048576  # KiB -> MB
    except (OSError, ValueError):
        return float("nan")


#: file sizes of the ratio edge measured: a file of this many bytes declaring all the budget admits
EDGE_FILES = (512 << 10, 1 << 20)


def _edge_steps(path: Path, folder: Path) -> dict[str, list[str]]:
    return {"convert_exr": ["convert", str(path), "--to", "exr", "-o", str(folder / "e.exr"), "--overwrite"],
            "convert_png": ["convert", str(path), "--to", "png", "-o", str(folder / "e.png"), "--overwrite"],
            "warp": ["warp", str(path), "-o", str(folder / "w.exr"), "--to", "fisheye:fov=180", "--size",
                     "1024x1024", "--overwrite"],
            "tonemap": ["tonemap", str(path), "-o", str(folder / "t.png"), "--overwrite"]}


def _measure_edge(lenslab: list[str], path: Path, folder: Path, base: float, key: str, what: str,
                  decoded: int, aim: float = AIM_HOSTILE_MB) -> None:
    from lenslab.bench.results import figure, mark

    for step, argv in _edge_steps(path, folder).items():
        mb, status = peak_mb(lenslab + argv)
        extra = max(mb - base, 0.0)
        ok = figure(f"memory.{key}{step}", f"{step} {what}: peak beyond the baseline", extra, "MB",
                    aim=aim, note=f"exit {status}; {extra / (decoded / 1e6):.2f} x the decoded image")
        print(f"  {step:12s} exit {status}  peak {mb:6.0f} MB  beyond baseline {extra:6.0f} MB  "
              f"({extra / (decoded / 1e6):.2f} x decoded)  {mark(ok)}")


def edge_at_budget(lenslab: list[str], folder: Path, base: float) -> None:
    """The files at the budget's edges, which it admits, through each command, against the 200 MB aim:
    the largest image any file may decode to (:data:`lenslab.io.budget.BASE_BYTES` of float32: a flat
    2:1 RGBA half EXR of :func:`lenslab.bench.bombs.edge_size`, tens of kB; ``memory.edge_*``), and for
    each size of :data:`EDGE_FILES` the largest a file of that size may decode to
    (:func:`lenslab.io.budget.allowed`: a flat EXR, JPEG and HEIC padded to that size by
    :func:`lenslab.bench.bombs.write_ratio_edge`; ``memory.edge_{format}_{KiB}k_*``)."""
    from lenslab.bench.bombs import EDGE_FORMATS, edge_size, write_edge, write_ratio_edge
    from lenslab.io.budget import BASE_BYTES, SMALL_RATIO, allowed

    path = write_edge(folder / "edge.exr")
    kb = path.stat().st_size / 1e3
    w, h = edge_size()
    print(f"a {kb:.0f} kB flat {w} x {h} RGBA EXR decoding to {w * h * 16 / 1e6:.0f} MB (what any file may decode "
          f"to: {BASE_BYTES / 1e6:.0f} MB):")
    _measure_edge(lenslab, path, folder, base, "edge_", f"a {kb:.0f} kB {w}x{h} file at the base budget",
                  w * h * 16)
    path.unlink()
    for size in EDGE_FILES:
        for fmt, (channels, ext) in EDGE_FORMATS.items():
            path = folder / f"edge-{size}{ext}"
            w, h = write_ratio_edge(path, size, fmt)
            decoded = w * h * channels * 4
            print(f"a {size / 1e6:.2f} MB flat {w} x {h} {fmt} decoding to {decoded / 1e6:.0f} MB (what a file of its "
                  f"size may decode to: {allowed(size) / 1e6:.0f} MB, {SMALL_RATIO} times its bytes):")
            # admitted as an image of its size: the aim of a valid image (AIM_FACTOR times it plus 200 MB)
            _measure_edge(lenslab, path, folder, base, f"edge_{fmt}_{size >> 10}k_",
                          f"a {size / 1e6:.2f} MB {w}x{h} {fmt} at the ratio budget", decoded,
                          aim=AIM_FACTOR * decoded / 1e6 + AIM_EXTRA_MB)
            path.unlink()


#: the enlarging warp measured: a source panorama of this size into an equirect of that size, to each format
ENLARGE_SOURCE, ENLARGE_OUTPUT, ENLARGE_FORMATS = (1024, 512), (8192, 4096), ("exr", "png")

def enlarging_warps(lenslab: list[str], folder: Path, base: float) -> None:
    """A warp into an output much larger than its source (:data:`ENLARGE_SOURCE` into :data:`ENLARGE_OUTPUT`, to
    each of :data:`ENLARGE_FORMATS`): the peak beyond the baseline against 1.5 times the output's float32 RGBA
    image plus the source's decoded float image plus 200 MB (``memory.enlarge_{format}``); the same warp of an RGBA
    panorama and through an ST map of the output's size, to EXR, against the same aim (``memory.enlarge_rgba_exr``,
    ``memory.enlarge_stmap_exr``)."""
    from lenslab.bench.results import figure, mark

    (sw, sh), (ow, oh) = ENLARGE_SOURCE, ENLARGE_OUTPUT
    path = folder / "pano.exr"
    subprocess.run([sys.executable, "-c", MAKE, f"{sw}x{sh}", str(path), "{}"], check=True)
    source_mb, output_mb = sw * sh * 3 * 4 / 1e6, ow * oh * 4 * 4 / 1e6
    aim = AIM_FACTOR * output_mb + source_mb + AIM_EXTRA_MB
    print(f"a {sw} x {sh} panorama ({source_mb:.0f} MB decoded) warped into {ow} x {oh} ({output_mb:.0f} MB of float32 "
          f"RGBA): aim peak beyond the baseline <= {aim:.0f} MB")
    for ext in ENLARGE_FORMATS:
        out = folder / f"enlarged.{ext}"
        mb, status = peak_mb(lenslab + ["warp", str(path), "-o", str(out), "--to", "equirect", "--size", f"{ow}x{oh}",
                                        "--overwrite"])
        extra = max(mb - base, 0.0)
        ok = figure(f"memory.enlarge_{ext}", f"warp a {sw}x{sh} panorama into {ow}x{oh} {ext}: peak beyond the "
                    "baseline", extra, "MB", aim=aim, note=f"exit {status}; {extra / output_mb:.2f} x the output's "
                    "float32 RGBA")
        print(f"  {ext:4s} exit {status}  peak {mb:6.0f} MB  beyond baseline {extra:6.0f} MB  "
              f"({extra / output_mb:.2f} x the output)  {mark(ok)}")
        out.unlink(missing_ok=True)
    rgba, st = folder / "pano-rgba.exr", folder / "enlarge-st.exr"
    subprocess.run([sys.executable, "-c", MAKE, f"{sw}x{sh}", str(rgba), "{'alpha': True}"], check=True)
    subprocess.run(lenslab + ["stmap", "--from", "equirect", "--to", "equirect", "--size", f"{ow}x{oh}", "--source-size",
                              f"{sw}x{sh}", "-o", str(st), "--quiet"], check=True)
    out = folder / "enlarged.exr"
    for key, what, argv in (("rgba_exr", "an RGBA panorama", [str(rgba), "--to", "equirect", "--size", f"{ow}x{oh}"]),
                            ("stmap_exr", "a panorama through an ST map", [str(path), "--stmap", str(st)])):
        mb, status = peak_mb(lenslab + ["warp", *argv, "-o", str(out), "--overwrite"])
        extra = max(mb - base, 0.0)
        ok = figure(f"memory.enlarge_{key}", f"warp {what} ({sw}x{sh}) into {ow}x{oh} exr: peak beyond the baseline",
                    extra, "MB", aim=aim, note=f"exit {status}; {extra / output_mb:.2f} x the output's float32 RGBA")
        print(f"  {key:9s} exit {status}  peak {mb:6.0f} MB  beyond baseline {extra:6.0f} MB  "
              f"({extra / output_mb:.2f} x the output)  {mark(ok)}")
        out.unlink(missing_ok=True)
    for p in (path, rgba, st):
        p.unlink()


def peak_mb(argv: list[str], cwd=None) -> tuple[float, int]:
    """(peak RSS in MB, exit status) of a command, as its own (see :data:`LAUNCHER`)."""
    with tempfile.TemporaryDirectory(prefix="lenslab-peak-") as d:
        peak = Path(d) / "peak"
        done = subprocess.run(launched(argv, peak), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=cwd)
        return read_peak_mb(peak), done.returncode


def run(args) -> int:
    from lenslab.bench.hostile import cases
    from lenslab.bench.results import figure, mark

    lenslab = [sys.executable, "-m", "lenslab"]
    with tempfile.TemporaryDirectory(prefix="lenslab-bench-memory-") as d:
        d = Path(d)
        base, _ = peak_mb(lenslab + ["info", "--formats"])
        print(f"baseline: lenslab info --formats peaks at {base:.0f} MB")
        if args.enlarging_only:
            enlarging_warps(lenslab, d, base)
            return 0
        worst, worst_name = 0.0, ""
        corpus = d / "corpus"
        for case in cases(corpus):
            out = d / f"out-{case.name}"
            out.mkdir()
            file = case.file if case.file.startswith("/") else str(corpus / case.file)
            argv = [a.format(file=file, src=str(corpus / "src.exr"), out=str(out)) for a in case.argv]
            mb, status = peak_mb(lenslab + argv)
            extra = max(mb - base, 0.0)
            print(f"  {case.name:30s} exit {status}  peak {mb:6.0f} MB  beyond baseline {extra:6.0f} MB")
            if extra > worst:
                worst, worst_name = extra, case.name
        ok = figure("memory.hostile_worst", "hostile inputs under 1 MB: worst peak beyond the baseline", worst,
                    "MB", aim=AIM_HOSTILE_MB, note=f"worst: {worst_name}")
        print(f"hostile corpus: worst {worst:.0f} MB beyond the baseline ({worst_name})  aim <= "
              f"{AIM_HOSTILE_MB:.0f} MB  {mark(ok)}")
        edge_at_budget(lenslab, d, base)
        if not args.valid:
            return 0
        enlarging_warps(lenslab, d, base)
        side = args.side
        image_mb = side * side * 12 / 1e6
        aim = AIM_FACTOR * image_mb + AIM_EXTRA_MB
        print(f"valid {side} x {side} images: decoded float {image_mb:.0f} MB, aim peak <= {aim:.0f} MB")
        for key, (name, opts) in FORMATS.items():
            path = d / name
            subprocess.run([sys.executable, "-c", MAKE, str(side), str(path), repr(opts)], check=True)
            steps = {"read": [sys.executable, "-c", f"import lenslab.io as l; l.read({str(path)!r})"],
                     "convert": lenslab + ["convert", str(path), "--to", "exr", "-o", str(d / f"c-{key}.exr"),
                                           "--overwrite"],
                     "warp": lenslab + ["warp", str(path), "-o", str(d / f"w-{key}.exr"), "--to",
                                        "fisheye:fov=180", "--from", "perspective:fov=90", "--size", "1024x1024",
                                        "--overwrite"]}
            for step, argv in steps.items():
                mb, status = peak_mb(argv)
                ratio = (mb - AIM_EXTRA_MB) / image_mb
                ok = figure(f"memory.{step}_{key}", f"{step} a valid {side}x{side} {key}: peak", mb, "MB",
                            aim=aim, note=f"file {path.stat().st_size / 1e6:.1f} MB; exit {status}; "
                            f"(peak - 200 MB) / image = {ratio:.2f}")
                print(f"  {step:8s} {key:6s} file {path.stat().st_size / 1e6:7.1f} MB  exit {status}  peak "
                      f"{mb:6.0f} MB  ({ratio:.2f} x image + 200 MB)  {mark(ok)}")
            path.unlink()
    return 0
