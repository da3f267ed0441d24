"""tracer: a reference ray tracer that renders scenes through any lenslab camera into HDR images.

  tracer render --scene cornell --camera fisheye:fov=180 --size 512x512 --spp 64 -o out.exr
  tracer bench                         ray-cast and path-tracing throughput, as ratios
  tracer scenes                        the built-in scenes

A warp checked against a direct render of the same view: lenslab validate (it renders with this tracer).
"""

from __future__ import annotations

import argparse
import math
import os
import sys
from pathlib import Path

from lenslab.jobs.arguments import (ArgumentParser, add_tone_option, finite_float, image_size, non_empty,
                                    non_negative_int, positive_float, positive_int)
from lenslab.jobs.funnel import run_command

DISPLAY_SUFFIXES = (".png", ".jpg", ".jpeg", ".ppm", ".pgm")
#: rows of 180 degrees of a render without --size (512 rows of a fisheye, a 1024 x 512 equirect)
DEFAULT_ROWS = 512


def _triple(text: str) -> tuple[float, float, float]:
    try:
        vals = tuple(float(v) for v in text.replace(" ", "").split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected X,Y,Z numbers, got {text!r}") from None
    if len(vals) != 3 or not all(math.isfinite(v) for v in vals):
        raise argparse.ArgumentTypeError(f"expected three comma-separated finite numbers X,Y,Z, got {text[:40]!r}")
    return vals


def _seed(text: str):
    if text.lower() == "none":
        return None
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"a seed is an integer or 'none', got {text!r}") from None


def _exposure(text: str):
    if text.strip().lower() == "auto":
        return "auto"
    try:
        return finite_float(text)
    except argparse.ArgumentTypeError:
        raise argparse.ArgumentTypeError(f"exposure is a number of stops or 'auto', got {text[:40]!r}") from None


def add_render_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--scene", default="cornell", type=non_empty,
                   help="built-in scene name (cornell, cornell-point, sky, furnace, plane, arealight) or a scene "
                        "file (.obj with .mtl, .ply, .stl, .toml); default cornell")
    p.add_argument("--handedness", choices=("right", "left"), default="right",
                   help="the frame of a mesh file (.obj, .ply, .stl): 'right' (default; Blender, Maya, Mitsuba "
                        "and most exporters) is mirrored x -> -x on import so the scene renders as those tools "
                        "show it; 'left' keeps a file already in lenslab's left-handed frame")
    p.add_argument("--env", metavar="EXR", type=non_empty,
                   help="HDR equirect panorama lighting the 'sky' scene (default: a constant sky)")
    p.add_argument("--camera", metavar="SPEC", type=non_empty,
                   help="lenslab lens spec, e.g. perspective:fov=60, equirect, fisheye:fov=180,mapping=equisolid "
                        "(default: the scene's own camera lens); an EXR that records its camera (a tracer render, a "
                        "lenslab warp) renders that view again: its lens, orientation, eye (unless --eye; the "
                        "scene's own for an image that records its camera at the origin, as a lenslab warp of a "
                        "photograph does) and size (unless --size); --yaw, --pitch, --roll, --look-at, --up and "
                        "--view are refused with it")
    p.add_argument("--size", type=image_size, metavar="WxH",
                   help="image size in pixels (default: a calibrated --camera's own (a camera file, an image that "
                        "records its camera, a spec with width= and height=) or the size stored in --camera-file, "
                        "else the lens's own frame at 512 rows: 512x512 for a fisheye or perspective view, 1024x512 "
                        "for a hammer map, 768x512 for pannini, a lensfun lens its calibration sensor's shape (768x512 for 3:2); a cube map or a tiled grid: square faces or tiles of "
                        "256 pixels in its layout, 768x512 for a 3x2 cube map; an equirect: square pixels, 1024x512 "
                        "for the whole sphere)")
    p.add_argument("--spp", type=positive_int, default=64,
                   help="samples per pixel (default 64); the maximum when --time-budget or --target-error is given")
    p.add_argument("-o", "--output", required=True, metavar="FILE",
                   help="output image (.exr keeps HDR and stores the camera in its header; .pfm also HDR)")
    p.add_argument("--view", metavar="NAME", help="the scene's named camera view to start from (default: its first)")
    p.add_argument("--camera-file", metavar="TOML",
                   help="camera(s) in TOML as written by lenslab (one camera, or tables of cameras picked by --view); "
                        "replaces --camera and the pose options; --size still resizes it")
    p.add_argument("--eye", type=_triple, metavar="X,Y,Z", help="camera position (default: the view's; a new eye keeps the view's direction)")
    p.add_argument("--look-at", type=_triple, metavar="X,Y,Z",
                   help="point the camera looks at (not with --yaw/--pitch/--roll)")
    p.add_argument("--up", type=_triple, metavar="X,Y,Z", help="up direction for --look-at (default 0,1,0)")
    p.add_argument("--yaw", type=finite_float, help="camera heading in degrees, turned right from the world's +z (instead of the view's "
                        "target); with --pitch and --roll a full orientation")
    p.add_argument("--pitch", type=finite_float, help="camera tilt up, degrees")
    p.add_argument("--roll", type=finite_float, help="camera roll about its axis, degrees")
    p.add_argument("--integrator", choices=("path", "direct"), default="path",
                   help="path: path tracing with MIS and Russian roulette (default); direct: direct lighting only")
    p.add_argument("--max-depth", type=non_negative_int, default=8, help="maximum bounces (default 8; 1 = direct light)")
    p.add_argument("--time-budget", type=positive_float, metavar="S", help="stop near S seconds: passes are sized from the measured speed to end within the "
                        "budget (the first pass, 2 samples per pixel, always runs)")
    p.add_argument("--target-error", type=positive_float, metavar="E",
                   help="stop once the image's noise falls below E: the RMS standard error of the pixel means, "
                        "relative to the image's mean value (0.01 = 1%%)")
    p.add_argument("--variance-out", metavar="FILE", help="also write the per-pixel variance of the mean (EXR/PFM)")
    p.add_argument("--seed", type=_seed, default=0,
                   help="random seed (default 0; the same seed gives the same image); 'none' puts samples at the "
                        "strata centres")
    from lenslab.tone import curve_names

    add_tone_option(p, "tone", default="hable",
                    help=f"tone curve for display outputs (.png, .jpg, .ppm): {', '.join(curve_names())} "
                         "(default hable; 'lenslab curves --list' describes them); EXR and PFM keep the linear radiance")
    p.add_argument("--exposure", type=_exposure, default=0.0, metavar="EV",
                   help="exposure in stops before the tone curve, or 'auto' (display outputs only; default 0)")
    p.add_argument("--threads", type=positive_int, help="worker threads (default: every core)")
    p.add_argument("--overwrite", action="store_true", help="replace existing output files (never an input)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar or summary")
    from lenslab.jobs.arguments import add_scheduler_options

    add_scheduler_options(p, skip_existing=False)
    p.add_argument("--tiles", type=positive_int, metavar="N",
                   help="with --scheduler: trace the image as N tiles of rows on the workers (default 16 per worker "
                        "thread); the image is bit for bit the one a local render with the same --seed makes")


def _camera(args, scene):
    from lenslab.lenses import Camera, make_lens

    if args.camera_file:
        from pathlib import Path

        from lenslab.inputs.safeload import load_toml
        from lenslab.inputs.sidefile import read_side_text

        path = Path(args.camera_file)
        doc = load_toml(read_side_text(path, "camera file", 4 << 20), path, ValueError)
        if "lens" not in doc:
            tables = {k: v for k, v in doc.items() if isinstance(v, dict) and "lens" in v}
            if not tables:
                raise ValueError(f"{path}: no camera found (expected a [lens] table, or tables of cameras)")
            name = next(iter(tables)) if args.view is None else args.view  # '' names none: never the first
            if name not in tables:
                from lenslab.errors import UsageError

                raise UsageError(f"--view {name!r}: {path} has no camera of that name; it has {', '.join(tables)}")
            doc = tables[name]
        cam = Camera.from_dict(doc)
        if args.size is not None and tuple(args.size) != cam.size:
            cam = Camera(cam.lens.with_size(*args.size), cam.pose)
        return cam
    recorded = _recorded_view(args, scene)
    if recorded is not None:
        return recorded
    from lenslab.jobs.warp.cameras import given_pose

    if args.look_at is not None and given_pose(args):  # (which of the two to drop cannot be told)
        from lenslab.errors import UsageError

        raise UsageError("give either --look-at or --yaw/--pitch/--roll, not both")
    pose = {}
    if args.eye is not None:
        pose["eye"] = args.eye
    if args.look_at is not None:
        pose["look_at"] = args.look_at
    if args.up is not None:
        pose["up"] = args.up
    for k in ("yaw", "pitch", "roll"):
        if getattr(args, k) is not None:
            pose[k] = getattr(args, k)
    if args.view is not None and args.view not in scene.views:
        from lenslab.errors import UsageError

        raise UsageError(f"--view {args.view!r}: scene {scene.name} has no view of that name; it has "
                         f"{', '.join(scene.views) or 'none'}")
    size = args.size or _calibrated_size(args.camera)
    if size is None:
        from lenslab.jobs.warp.cameras import default_size

        # the lens's own frame (--camera's, else the scene view's) at 512 rows of 180 degrees, as lenslab warp's without
        # a source: a hammer map 2:1, a cube map's faces of 256 pixels in its layout, an equirect's square pixels
        size = default_size(args.camera or scene.view(args.view).lens, DEFAULT_ROWS)
    if args.camera:
        make_lens(args.camera, size)  # report a bad spec before anything else
    return scene.camera(args.camera, size, view=args.view, **pose)


def _recorded_view(args, scene):
    """``--camera render.exr`` (an image whose header records its camera, as tracer and lenslab warp write it): the
    view of that render, its lens, orientation and eye (or ``--eye``; the scene view's when the file records its
    camera at the origin, which places nothing: a panorama lenslab made of a photograph), at its size unless --size
    is given; None for a lens spec or a calibration file. Options that would turn it are a usage error, as with ``lenslab warp --to
    render.exr``: whether they turn the render's view or the world's cannot be told."""
    from lenslab.jobs.warp.cameras import recorded_view, refuse_turns

    view = recorded_view(args.camera)
    if view is None:
        return None
    turns = [flag for flag, value in (("--view", args.view), ("--look-at", args.look_at), ("--up", args.up),
                                      ("--yaw", args.yaw), ("--pitch", args.pitch), ("--roll", args.roll))
             if value is not None]
    refuse_turns(turns, "--camera", args.camera, view)
    import numpy as np

    from lenslab.lenses import Camera, Pose

    lens = view.lens if args.size is None or tuple(args.size) == view.size else view.lens.with_size(*args.size)
    eye = view.pose.eye if args.eye is None else np.asarray(args.eye, dtype=np.float64)
    if args.eye is None and not np.any(eye):
        eye = scene.camera(None, (lens.width, lens.height)).pose.eye
    return Camera(lens, Pose(view.pose.rotation, eye))


def _calibrated_size(spec: str | None) -> tuple[int, int] | None:
    """The image size a camera was calibrated at: a camera file's (or an image's recorded camera), a spec's
    ``width=`` and ``height=``; None for a model spec without one."""
    from lenslab.calibfiles import is_camera_file
    from lenslab.lenses import make_lens, parse_spec

    if not spec:
        return None
    if is_camera_file(spec):
        lens = make_lens(spec)
        return lens.width, lens.height
    values = parse_spec(spec)[1]
    if values.get("width") and values.get("height"):
        return int(float(values["width"])), int(float(values["height"]))
    return None


def run_render(args) -> int:
    import gc

    # a render's reference cycles come from imports and numba's set-up, not from tracing (arrays, freed by
    # their counts): collecting them while it runs costs about 0.1 s of CPU for nothing
    gc.disable()
    try:
        return _render(args)
    except BaseException as exc:
        from lenslab.errors import stop_signal

        if stop_signal(exc) is not None:  # Ctrl-C, SIGTERM, SIGHUP: the note is the command's last line
            _close_bars()
        raise
    finally:
        gc.enable()


def _close_bars() -> None:
    """Close the progress bars an interrupt left open (one would redraw itself after the note), and clear
    the terminal's line of one the interrupt caught while it was being drawn."""
    if "tqdm" in sys.modules:
        from tqdm import tqdm

        for bar in list(getattr(tqdm, "_instances", ())):
            try:
                bar.close()
            except AttributeError:  # one the interrupt caught half-built: the line is cleared below
                tqdm._instances.discard(bar)
    if sys.stderr.isatty():  # bars are drawn on a terminal only
        sys.stderr.write("\r\033[K")
        sys.stderr.flush()


def _render(args) -> int:
    from lenslab.errors import UsageError
    from lenslab.jobs.policy import check_output
    from tracer.load import check_scene_argument, load_scene
    from tracer.rendering import render

    check_scene_argument(args.scene)
    inputs = [f for f in (args.env, args.camera_file, args.camera, args.scene) if f and Path(f).exists()]
    for out in (args.output, args.variance_out):
        if out:
            check_output(out, inputs, args.overwrite)
    if args.variance_out and same_path(args.variance_out, args.output):
        raise UsageError("--variance-out must name another file than -o")
    from lenslab.io.registry import hdr_formats
    from lenslab.jobs.policy import output_format

    output_format(args.output)  # an unknown extension: a usage error before the render, not after it
    if args.variance_out and output_format(args.variance_out) not in hdr_formats():
        raise UsageError(f"--variance-out {args.variance_out}: the variance is linear; write EXR or PFM")
    from lenslab.staging import sweep

    sweep({Path(out).parent for out in (args.output, args.variance_out) if out})  # temporaries of killed runs
    kwargs = {"env": args.env} if args.env else {}
    if Path(args.scene).suffix.lower() in (".obj", ".ply", ".stl", ".vtk", ".vtp"):
        kwargs["handedness"] = args.handedness
    elif args.handedness != "right":
        raise UsageError("--handedness applies to a mesh file (.obj, .ply, .stl); a TOML scene says it per "
                         "[[mesh]] (handedness = \"left\") and built-in scenes have their own frame")
    if args.env and args.scene != "sky":
        raise ValueError("--env lights the built-in 'sky' scene; a TOML scene names its own [environment]")
    from lenslab.tone import get_curve

    get_curve(args.tone)  # a bad curve name fails now, not after the render
    if Path(args.output).suffix.lower() not in DISPLAY_SUFFIXES and args.exposure != 0.0:
        raise UsageError("--exposure applies to display outputs (.png, .jpg, .ppm); EXR and PFM keep the radiance")
    scene = load_scene(args.scene, **kwargs)
    if scene.dropped and not args.quiet:
        print(f"tracer render: {scene.dropped} degenerate (zero-area) triangles dropped from {args.scene}",
              file=sys.stderr)
    camera = _camera(args, scene)
    from lenslab.jobs.warp.cameras import note_size

    note_size(camera.lens)  # a size off the lens's layout (a cube map's faces not square): one note
    from tracer.tiles import render_on_cluster

    if args.handedness != "right" and (args.scheduler or args.scheduler_file or os.environ.get("DASK_SCHEDULER_ADDRESS")):
        raise UsageError("--handedness left renders on this machine only; workers load mesh files right-handed")
    result = render_on_cluster(args, camera)  # None without --scheduler (or DASK_SCHEDULER_ADDRESS)
    if result is None:
        result = render(scene, camera, spp=args.spp, seed=args.seed, integrator=args.integrator,
                        max_depth=args.max_depth, progress=not args.quiet, time_budget=args.time_budget,
                        target_error=args.target_error, threads=args.threads)
    if Path(args.output).suffix.lower() in DISPLAY_SUFFIXES:
        from lenslab.io import write
        from lenslab.tone import tonemap

        exposure = args.exposure
        shown = result.rgba if float(result.alpha.min()) < 1 else result.image
        write(args.output, tonemap(shown, args.tone, exposure=exposure), overwrite=args.overwrite)
        if args.variance_out:
            result.save(None, args.variance_out, overwrite=args.overwrite)
    else:
        result.save(args.output, args.variance_out, overwrite=args.overwrite)
    if not args.quiet:
        rate = result.info["samples_per_second"]
        stopped = {"time": ", stopped by --time-budget", "error": ", stopped by --target-error"}
        print(f"{args.output}: {camera.width}x{camera.height} {camera.lens.spec()}, {result.spp} spp"
              f"{stopped.get(result.stopped_by, '')}, {result.seconds:.2f} s, {rate / 1e6:.3f} Msamples/s, "
              f"noise {_noise(result.relative_error)}", file=sys.stderr)
    return 0


def _noise(x: float) -> str:
    if x == float("inf"):
        return "unknown (fewer than 2 samples per pixel)"
    return f"{100 * x:.3g}% (RMS standard error of the pixel means, relative to the image's mean value)"


def same_path(a, b) -> bool:
    return Path(a).absolute() == Path(b).absolute()


def build_parser() -> argparse.ArgumentParser:
    parser = ArgumentParser(prog="tracer", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    p = sub.add_parser("render", help="render a scene through a lenslab camera",
                       description="Render a scene through any lenslab camera into an HDR image; the camera is "
                                   "written into the EXR header.")
    add_render_arguments(p)
    p.set_defaults(_run=run_render)
    from tracer import bench

    b = sub.add_parser("bench", help="ray-cast and path-tracing throughput", description=bench.__doc__,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    bench.add_arguments(b)
    b.set_defaults(_run=bench.run)
    s = sub.add_parser("scenes", help="list the built-in scenes")
    s.set_defaults(_run=run_scenes)
    for q in (parser, p, b, s):
        q.add_argument("--debug", action="store_true", default=False if q is parser else argparse.SUPPRESS,
                       help="on an error, print the full traceback too")
    return parser


def run_scenes(args) -> int:
    from tracer.builtin import BUILTINS
    from tracer import builtin

    print((builtin.__doc__ or "").strip())
    print("\nnames: " + ", ".join(BUILTINS))
    return 0


def main(argv=None) -> int:
    words = sys.argv[1:] if argv is None else list(argv)
    if words[:1] == ["render"] and "numpy" not in sys.modules:
        from tracer.process import prepare_render

        prepare_render()  # BLAS on one thread, freed memory kept: see tracer.process
    parser = build_parser()
    args = parser.parse_args(argv)  # a usage error: one line on stderr and SystemExit(2)
    return run_command(args._prog, lambda: args._run(args), debug=getattr(args, "debug", False))


if __name__ == "__main__":
    sys.exit(main())
