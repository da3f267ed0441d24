"""Trace the built-in Cornell box once, warp it into every lens and build the HTML gallery.

With no input at all, the demo:

  1. traces the Cornell box as a full-sphere HDR panorama from a point inside the box;
  2. warps that one panorama into every lens model: the four fisheye mappings, the
     tan-warped fisheye, swirl, pincushion, barrel, Brown distortion, perspective, cube map, a 2x2
     multi-view (four cameras sharing the panorama's eye, each with its own pose) and a little planet
     (a stereographic fisheye looking straight down with a very wide field of view);
  3. traces two of those views directly (the equisolid fisheye and the 2x2 multi-view) and measures the
     warp against them: relative L1 error, the direct trace's own noise, and the time of each;
  4. tone-maps one view with every tone curve;
  5. writes EXR (with the camera in the header), PFM, PPM and JPG files, builds index.html and prints
     where it is.

--quality fast (the default) finishes in well under a minute on two cores; --quality full traces
bigger and cleaner images in several minutes. --size, --view-size, --spp and --direct-spp override
either preset.

What it writes: index.html (open it in a browser) with style.css and its images in img/;
panorama.exr/.pfm/.ppm/.jpg; views/NAME.exr and .jpg for every lens; direct/NAME.exr, .pfm and .jpg
for the two direct traces; tone/CURVE.jpg for every tone curve; gallery.json, the records
'python -m gallery DIR' rebuilds the page from.

The output folder must be new or empty: the demo refuses to write into a folder that holds anything,
so it never mixes its files with yours. With --overwrite it writes into the folder anyway, replacing
the files it makes (each one written to a temporary name first, then renamed) and leaving every other
file alone.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from lenslab.errors import UsageError
from lenslab.jobs.arguments import positive_int

HELP = "trace the built-in Cornell box, warp it into every lens and build the HTML gallery"
DEFAULT_OUT = "lenslab-demo"

# quality -> panorama size, panorama spp, view side, direct-trace spp
PRESETS = {
    "fast": {"size": (1024, 512), "spp": 8, "view": 256, "direct_spp": 32},
    "full": {"size": (2048, 1024), "spp": 32, "view": 512, "direct_spp": 128},
}

SCENE = "cornell"
INTEGRATOR = "path"
MAX_DEPTH = 8
# The eye: inside the box, centred left-right, a little above mid height, 6 cm in from its open front
# (metres), so a forward fisheye sees all five walls, both blocks and the light.
EYE = (0.278, 0.30, 0.06)
WARP = {"filter": "bilinear", "samples": 1, "antialias": True}
COMPARED = ("fisheye, equisolid", "2x2 multi-view")
SAMPLE_CURVE_VIEW = "fisheye, equisolid"  # the view the tone curves are compared on


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("-o", "--output", type=Path, default=Path(DEFAULT_OUT), metavar="DIR",
                        help=f"output folder (default: {DEFAULT_OUT}/); must be new or empty unless --overwrite")
    parser.add_argument("--quality", choices=sorted(PRESETS), default="fast",
                        help="fast: 1024x512 panorama at 8 spp, 256 px views, direct traces at 32 spp, well under a "
                             "minute (default); "
                             "full: 2048x1024 at 32 spp, 512 px views, direct traces at 128 spp, several minutes")
    parser.add_argument("--size", metavar="WxH", type=_size,
                        help="panorama size, width twice the height (default: from --quality)")
    parser.add_argument("--view-size", metavar="N", type=positive_int,
                        help="side of the square views in pixels (default: from --quality)")
    parser.add_argument("--spp", type=positive_int, metavar="N",
                        help="samples per pixel of the panorama (default: from --quality)")
    parser.add_argument("--direct-spp", type=positive_int, metavar="N",
                        help="samples per pixel of the two direct traces (default: from --quality)")
    parser.add_argument("--seed", type=int, default=0, help="random seed of the traces (default: 0)")
    parser.add_argument("--hdri", type=Path, metavar="DIR",
                        help="also warp your own equirect HDR panoramas (.exr/.pfm in DIR) into a couple of lenses")
    parser.add_argument("--report", type=Path, metavar="DIR",
                        help="add the speed/accuracy plot of a 'lenslab validate' report folder")
    parser.add_argument("--overwrite", action="store_true",
                        help="write into a folder that is not empty, replacing the demo's own files there")
    parser.add_argument("--quiet", action="store_true", help="no progress bar and no report, only the gallery path")


def _size(text: str) -> tuple[int, int]:
    try:
        w, h = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not WIDTHxHEIGHT, e.g. 1024x512") from None
    if h < 2 or w != 2 * h:
        raise argparse.ArgumentTypeError(f"{text!r}: a full-sphere panorama is twice as wide as high, e.g. 1024x512")
    return w, h


def check_output(out: Path, overwrite: bool) -> None:
    """Refuse a non-empty folder (or a file) unless ``overwrite``; create the folder."""
    if out.exists() and not out.is_dir():
        raise FileExistsError(f"{out} is a file, not a folder; choose another output folder with -o")
    if out.is_dir() and any(out.iterdir()) and not overwrite:
        raise FileExistsError(f"{out} is not empty; choose a new folder with -o DIR, or give --overwrite to "
                              "write into it (the demo's own files there are replaced, others are kept)")
    out.mkdir(parents=True, exist_ok=True)


def slug(text: str) -> str:
    import re

    return re.sub(r"[^a-z0-9]+", "-", text.lower()).strip("-")


def make_camera(v: dict, eye):
    from lenslab.lenses import REGISTRY, Camera, Pose, make_lens

    w, h = v["size"]
    if "tiles" in v:
        lens = REGISTRY["tiled"](w, h, grid=v["spec"].partition(":")[2] or "2x2", tiles=v["tiles"])
    else:
        lens = make_lens(v["spec"], (w, h))
    p = v["pose"]
    return Camera(lens, Pose.from_ypr(p.get("yaw", 0.0), p.get("pitch", 0.0), p.get("roll", 0.0), eye))


class Run:
    """Writes the demo's files and remembers them, with a progress bar over the steps."""

    def __init__(self, out: Path, total: int, quiet: bool):
        from tqdm import tqdm

        self.out = out
        self.files: list[dict[str, str]] = []
        self.quiet = quiet
        self.bar = tqdm(total=total, desc="demo", unit="step", file=sys.stderr, leave=False,
                        disable=quiet or not sys.stderr.isatty(),
                        bar_format="{desc}: {percentage:3.0f}%|{bar}| {n_fmt}/{total_fmt} [{elapsed}<{remaining}]")

    def step(self, desc: str) -> None:
        self.bar.set_description_str(desc)

    def done(self, n: int = 1) -> None:
        self.bar.update(n)

    def say(self, line: str = "") -> None:
        if not self.quiet:
            self.bar.write(line, file=sys.stdout)

    def write(self, rel: str, image, what: str, **options) -> str:
        from lenslab.io import write

        path = self.out / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        write(path, image, overwrite=True, **options)
        fmt = path.suffix.lstrip(".").upper()
        self.files.append({"path": rel, "format": fmt, "what": what})
        return rel

    def close(self) -> None:
        self.bar.close()


def run(args: argparse.Namespace) -> int:
    t_start = time.perf_counter()
    preset = PRESETS[args.quality]
    pano_size = args.size or preset["size"]
    view = args.view_size or preset["view"]
    spp = args.spp or preset["spp"]
    direct_spp = args.direct_spp or preset["direct_spp"]
    out: Path = args.output
    for name, folder in (("--hdri", args.hdri), ("--report", args.report)):
        if folder is not None and not folder.is_dir():
            raise FileNotFoundError(f"{name} {folder}: no such folder")
        if folder is not None and folder.resolve() == out.resolve():
            raise UsageError(f"{name} {folder} is an input of the demo; it is never written into, even with "
                              "--overwrite: give another output folder with -o")
    check_output(out, args.overwrite)

    from gallery import build_gallery
    from gallery.items import Display, FileList, Panorama, RunInfo

    from gallery.views import lens_views

    views = lens_views(view)
    compared = [v for v in views if v["name"] in COMPARED]
    run_ = Run(out, total=2 + len(views) + len(compared) + 2, quiet=args.quiet)
    try:
        run_.say(f"lenslab demo: the {SCENE} box, a {pano_size[0]}x{pano_size[1]} panorama at {spp} spp, "
                 f"{len(views)} lenses at {view} px ({args.quality} quality)")
        scene, pcam, pano, ev = trace_panorama(run_, pano_size, spp, args.seed)
        records, warped = warp_views(run_, views, pcam, pano.image, ev)
        for v in compared:
            compare_view(run_, scene, records[v["name"]], warped[v["name"]], direct_spp, args.seed + 1, ev)
        tone = tone_curves(run_, records, warped, ev)

        run_.step("building the gallery")
        items = [
            Display(curve="hable", exposure=ev),
            Panorama(path="panorama.exr", spec=pcam.lens.spec(), size=pano_size, scene=SCENE, spp=pano.spp,
                     seconds=pano.seconds, eye=EYE, integrator=INTEGRATOR, max_depth=MAX_DEPTH),
            *[records[v["name"]] for v in views],
            tone,
            FileList(files=list(run_.files)),
            RunInfo(command=_command_line(args), seconds=time.perf_counter() - t_start,
                    settings={"quality": args.quality, "panorama": f"{pano_size[0]}x{pano_size[1]} at {spp} spp",
                              "views": f"{view} px", "direct traces": f"{direct_spp} spp"}),
        ]
        index = build_gallery(out, *items, validate_report=args.report, hdri_dir=args.hdri,
                              title="lenslab demo: one panorama, every lens")
        run_.done()
    finally:
        run_.close()
    if not args.quiet:
        kinds = sorted({f["format"] for f in run_.files})
        print(f"wrote {len(run_.files)} image files ({', '.join(kinds)}) under {out}/ "
              f"in {time.perf_counter() - t_start:.1f} s in total")
    print(f"gallery: {index}")
    return 0


def trace_panorama(run_: Run, size: tuple[int, int], spp: int, seed: int):
    """Trace the scene's panorama from :data:`EYE` and write it as EXR, PFM, PPM and JPG.

    Returns the scene, the panorama camera, the render and the display exposure (auto, from the panorama).
    """
    import numpy as np

    import tracer
    from lenslab.lenses import Camera, Pose, make_lens
    from lenslab.tone import auto_exposure, tonemap

    run_.step("loading the scene")
    scene = tracer.load_scene(SCENE)
    pcam = Camera(make_lens("equirect", size), Pose(eye=np.asarray(EYE)))
    run_.step(f"tracing the panorama ({spp} spp)")
    pano = tracer.render(scene, pcam, spp=spp, seed=seed, integrator=INTEGRATOR, max_depth=MAX_DEPTH)
    pano.image = np.ascontiguousarray(pano.image, dtype=np.float32)
    run_.done()
    ev = auto_exposure(pano.image)
    run_.say(f"traced the panorama {size[0]}x{size[1]}, {spp} spp, {INTEGRATOR} depth {MAX_DEPTH}: "
             f"{pano.seconds:.1f} s (display exposure {ev:+.2f} EV, auto)")
    run_.step("writing the panorama")
    display = tonemap(pano.image, curve="hable", exposure=ev)
    run_.write("panorama.exr", pano.image, "the traced HDR panorama, with its camera in the header", camera=pcam)
    run_.write("panorama.pfm", pano.image, "the same HDR panorama as PFM (32-bit float)")
    run_.write("panorama.ppm", display, "tone-mapped (hable), 16-bit PPM", bits=16)
    run_.write("panorama.jpg", display, "tone-mapped (hable), JPG")
    run_.done()
    return scene, pcam, pano, ev


def warp_views(run_: Run, views: list[dict], pcam, pano_image, ev: float):
    """Warp the panorama into every view; write each as EXR (RGBA, camera) and JPG.

    Returns the :class:`gallery.items.LensView` records and ``name -> (image, alpha, camera)``.
    """
    import numpy as np

    from gallery.items import LensView
    from lenslab.tone import tonemap
    from lenslab.warp import warp

    records: dict[str, LensView] = {}
    warped: dict[str, tuple] = {}
    first_calls = 0.0
    for v in views:
        run_.step(f"warping: {v['name']}")
        cam = make_camera(v, EYE)
        # The first call of a lens's code path also compiles its warp kernels (once per machine: they
        # are cached on disk); the second call is the warp's own time.
        t0 = time.perf_counter()
        warp(pano_image, pcam, cam, **WARP)
        first = time.perf_counter() - t0
        t0 = time.perf_counter()
        img, alpha = warp(pano_image, pcam, cam, **WARP)
        seconds = time.perf_counter() - t0
        first_calls += first
        s = slug(v["name"])
        rgba = np.concatenate([img, alpha[..., None]], axis=-1).astype(np.float32)
        rel = run_.write(f"views/{s}.exr", rgba, f"{v['name']}: warped HDR with alpha and camera", camera=cam)
        run_.write(f"views/{s}.jpg", tonemap(img, curve="hable", exposure=ev), f"{v['name']}: tone-mapped")
        warped[v["name"]] = (img, alpha, cam)
        records[v["name"]] = LensView(
            name=v["name"], spec=v["spec"], size=tuple(cam.size),
            warped=rel, warp_seconds=seconds, pose={k: float(x) for k, x in v["pose"].items()},
            settings=dict(WARP), note=v["note"])
        run_.done()
    total = sum(r.warp_seconds for r in records.values())
    compiling = max(first_calls - total, 0.0)
    run_.say(f"warped the panorama into {len(views)} lenses in {total:.2f} s (bilinear with the footprint prefilter)"
             + (f"; the first calls, which compile or load the warp kernels, took {compiling:.1f} s more"
                if compiling >= 1.0 else ""))
    return records, warped


def compare_view(run_: Run, scene, record, warped, spp: int, seed: int, ev: float) -> None:
    """Trace a view directly, write it, and store the warp's error against it in ``record``."""
    import numpy as np

    import tracer
    from lenslab import metrics
    from lenslab.tone import tonemap

    img, alpha, cam = warped
    name = record.name
    run_.step(f"tracing directly: {name} ({spp} spp)")
    ref = tracer.render(scene, cam, spp=spp, seed=seed, integrator=INTEGRATOR, max_depth=MAX_DEPTH)
    s = slug(name)
    ref_rgba = np.concatenate([ref.image, ref.alpha[..., None]], axis=-1).astype(np.float32)
    rel = run_.write(f"direct/{s}.exr", ref_rgba, f"{name}: traced directly, with alpha and camera", camera=cam)
    run_.write(f"direct/{s}.pfm", ref.image, f"{name}: traced directly, PFM")
    run_.write(f"direct/{s}.jpg", tonemap(ref.image, curve="hable", exposure=ev), f"{name}: traced directly, tone-mapped")
    valid = metrics.valid_mask(ref.alpha, alpha)
    edges = metrics.edge_mask_from_image(ref.image, radius=2, mask=valid)
    stats = metrics.compare(ref.image, img, ref.alpha, alpha, edges=edges,
                            ref_stderr=np.sqrt(np.maximum(ref.variance, 0.0)), with_flip=False)
    keys = ("l1", "l1_interior", "l1_edge", "noise_l1", "excess_l1", "psnr_log")
    record.direct, record.trace_seconds, record.trace_spp = rel, ref.seconds, ref.spp
    record.error = {k: float(stats[k]) for k in keys if stats.get(k) is not None}
    run_.say(f"  {name:<22s} warp {record.warp_seconds * 1e3:6.0f} ms   direct trace {ref.seconds:6.2f} s "
             f"({spp} spp)   relative L1 {100 * stats['l1']:.2f}% "
             f"(the direct trace's own noise alone: {100 * (stats.get('noise_l1') or 0):.2f}%)")
    run_.done()


def tone_curves(run_: Run, records: dict, warped: dict, ev: float):
    """Tone-map one view with every curve (JPG each, and a PPM); returns its :class:`gallery.items.ToneSet`."""
    from gallery.items import ToneSet
    from lenslab.tone import curve_names, tonemap

    run_.step("tone curves")
    name = SAMPLE_CURVE_VIEW if SAMPLE_CURVE_VIEW in warped else next(iter(warped))
    image = warped[name][0]
    curves = curve_names()
    from lenslab.tone.registry import get_curve

    for c in curves:  # a curve that ignores the exposure (mantiuk) is given none, so the demo prints no note for it
        stops = 0.0 if get_curve(c).ignores_exposure else ev
        run_.write(f"tone/{c}.jpg", tonemap(image, curve=c, exposure=stops), f"tone curve {c}")
    run_.write("tone/hable.ppm", tonemap(image, curve="hable", exposure=ev), "tone curve hable, 8-bit PPM")
    run_.say(f"tone-mapped the {name} view with {len(curves)} curves: {', '.join(curves)}")
    run_.done()
    return ToneSet(source=records[name].warped, curves=curves, exposure=ev, label=f"{name} view, auto")


def _command_line(args: argparse.Namespace) -> str:
    parts = ["lenslab", "demo"]
    if args.output != Path(DEFAULT_OUT):
        parts += ["-o", str(args.output)]
    if args.quality != "fast":
        parts += ["--quality", args.quality]
    if args.size:
        parts += ["--size", f"{args.size[0]}x{args.size[1]}"]
    for flag, value in (("--view-size", args.view_size), ("--spp", args.spp), ("--direct-spp", args.direct_spp)):
        if value:
            parts += [flag, str(value)]
    return " ".join(parts)
