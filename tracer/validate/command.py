"""Check warps against direct ray-traced renders, and measure the speed/accuracy trade.

Renders the reference view directly through the target camera, renders equirect panoramas from the same
eye at each size, warps each into the target camera with each setting, and compares: relative L1,
PSNR of log radiance, share of pixels off by more than 5% and FLIP, over the valid pixels, on the
edges (within 2 px of silhouettes and shadow edges) and away from them, next to the reference's own
Monte Carlo noise. Writes REPORT/results.json, REPORT/report.md and plots.

Two modes:
  Monte Carlo (default)  the whole pipeline: path-traced panoramas and reference, noise included.
  --noise-free           resampling error alone: fixed sub-pixel sample positions and a point light
                         (the Cornell box becomes cornell-point, its light 15 cm under the ceiling,
                         rendered with the direct integrator).
                         --scene analytic is a noise-free environment with no geometry, whose radiance
                         is a closed-form function of direction (no tracer needed).

Warp settings (--filters): a filter (lenslab.filters.FILTERS); 'antialias' is bilinear with the
footprint prefilter (which replaces the filter); append @KxK for sub-samples: bilinear@2x2.

Examples:
  lenslab validate --scene cornell --to fisheye:fov=180,mapping=equisolid -o report/
  lenslab validate --noise-free --to swirl:amount=6 --size 256x256 --pano-sizes 1024x512,2048x1024 -o r/
  lenslab validate --noise-free --tune 0.5% -o r/          # cheapest setting within 0.5% relative L1
  lenslab validate --noise-free --amortised -o r/          # K views: one panorama + K warps vs K renders
  lenslab validate --reference photo.exr --reference-camera fisheye:fov=180 --source pano.exr -o r/
                                                          # your own reference: lenslab diff's report per setting
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from lenslab.jobs.arguments import finite_float, finite_vector, image_size, non_empty, non_negative_int, positive_int

# the files a report holds (lenslab.validate.report): an earlier run's are replaced only with --overwrite
REPORT_FILES = ("results.json", "report.md")

HELP = "check warps against direct ray-traced renders and measure the speed/accuracy trade"


def _percent(text: str) -> float:
    t = text.strip()
    try:
        x = float(t[:-1]) / 100.0 if t.endswith("%") else float(t)
    except ValueError:
        x = float("nan")
    if not 0.0 < x < float("inf"):
        raise argparse.ArgumentTypeError(f"{text[:40]!r} is not an error like 0.005 or 0.5%")
    return x


def _int_list(text: str) -> list[int]:
    if text.strip().lower() == "none":
        return []
    try:
        vals = [int(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a comma-separated list of integers") from None
    if not vals:
        raise argparse.ArgumentTypeError("is empty; give sample counts such as 1,4,16, or 'none' to skip")
    if any(v < 1 for v in vals):
        raise argparse.ArgumentTypeError("sample counts must be at least 1")
    return vals


def _vec3(text: str) -> tuple[float, float, float]:
    return finite_vector(text)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    from lenslab.filters import FILTERS

    parser.add_argument("--scene", default="cornell", type=non_empty,
                        help="tracer scene to render (default cornell; any built-in or scene file of the "
                             "tracer), or 'analytic' for the noise-free analytic environment")
    parser.add_argument("--to", dest="to", default="fisheye:fov=180,mapping=equisolid", metavar="SPEC",
                        help="target lens spec (default fisheye:fov=180,mapping=equisolid)")
    parser.add_argument("--size", type=image_size, default=(512, 512), metavar="WxH",
                        help="target image size (default 512x512)")
    parser.add_argument("--yaw", type=finite_float, default=None,
                        help="target yaw in degrees (default: the scene's view; 0 where --pitch or --roll is given)")
    parser.add_argument("--pitch", type=finite_float, help="target pitch in degrees (default 0, or the scene's view)")
    parser.add_argument("--roll", type=finite_float, help="target roll in degrees (default 0, or the scene's view)")
    parser.add_argument("--eye", type=_vec3, default=None, metavar="X,Y,Z",
                        help="target (and panorama) eye point (default: the scene's default view)")
    parser.add_argument("--look-at", type=_vec3, default=None, metavar="X,Y,Z",
                        help="point the target looks at (default: the scene's default view); not with "
                             "--yaw/--pitch/--roll")
    parser.add_argument("--pano-sizes", default="1024x512,2048x1024,4096x2048", metavar="LIST",
                        help="panorama sizes to render and warp from (default 1024x512,2048x1024,4096x2048)")
    parser.add_argument("--filters", default="bilinear,bilinear@2x2,antialias,lanczos", metavar="LIST",
                        help="warp settings to compare (default bilinear,bilinear@2x2,antialias,lanczos); filters: "
                             + ", ".join(FILTERS))
    parser.add_argument("--spp", type=positive_int, default=None,
                        help="samples per pixel of the panoramas (default 1 noise-free, 16 Monte Carlo)")
    ref = parser.add_mutually_exclusive_group()
    ref.add_argument("--reference-spp", type=positive_int, default=None, metavar="N",
                     help="samples per pixel of the reference (default 64 noise-free, 1024 Monte Carlo)")
    ref.add_argument("--reference-error", type=_percent, default=None, metavar="E",
                     help="render the reference with enough samples that its own noise reads as at most E "
                          "relative L1 (e.g. 0.1%%)")
    parser.add_argument("--direct-spp", type=_int_list, default=None, metavar="LIST",
                        help="also render the target directly at these sample counts, the alternative to "
                             "warping, for the plot, --tune and --amortised (default 1,4,16; 'none' to skip)")
    parser.add_argument("--noise-free", action="store_true",
                        help="measure resampling error alone: fixed sample positions and a point light")
    parser.add_argument("--integrator", default=None, choices=("path", "direct"),
                        help="tracer integrator (default path; direct in --noise-free)")
    parser.add_argument("--max-depth", type=non_negative_int, default=8, help="path length limit (default 8)")
    parser.add_argument("--seed", type=int, default=0, help="random seed of the Monte Carlo renders")
    parser.add_argument("--repeat", type=positive_int, default=3, help="time each warp as the best of N runs (default 3)")
    parser.add_argument("--no-flip", action="store_true", help="skip the FLIP metric (the slowest one)")
    parser.add_argument("--tune", type=_percent, default=None, metavar="TARGET",
                        help="choose the cheapest panorama size, setting and samples reaching TARGET relative "
                             "L1 (e.g. 0.5%%), from the table and a fitted model")
    parser.add_argument("--amortised", action="store_true",
                        help="also measure K views (fisheye, swirl, pincushion, 2x2 tiles) from one panorama "
                             "against K direct renders at equal error, K = 1, 4, 16")
    parser.add_argument("--amortised-size", type=image_size, default=(256, 256), metavar="WxH",
                        help="view size for --amortised (default 256x256)")
    own = parser.add_argument_group("against your own reference (lenslab diff's report per warp setting)")
    own.add_argument("--reference", metavar="FILE",
                     help="your render or photograph of the view: warps are measured against it instead of a "
                          "direct render (writes DIR/reference.json and DIR/reference.md)")
    own.add_argument("--reference-camera", metavar="SPEC",
                     help="the lens of --reference (default: the camera its file records, else --to; an image "
                          "named here gives its lens and the mirror warp --flip recorded); posed by "
                          "--yaw/--pitch/--roll and --eye")
    own.add_argument("--source", metavar="FILE",
                     help="the image to warp into it (default: a panorama of --scene at the largest "
                          "--pano-sizes, rendered from the reference's eye)")
    own.add_argument("--from", dest="source_spec", metavar="SPEC",
                     help="the lens of --source (default: its recorded camera, else equirect for 2:1)")
    own.add_argument("--allow-parallax", action="store_true",
                     help="measure even when the reference's eye differs from the source's")
    from lenslab.jobs.diff_arguments import add_threshold_arguments

    add_threshold_arguments(parser)
    parser.add_argument("-o", "--output", required=True, metavar="DIR", help="report directory (created)")
    parser.add_argument("--overwrite", action="store_true", help="replace the report of an earlier run in DIR")
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    from lenslab.jobs.arguments import add_scheduler_options

    add_scheduler_options(parser, skip_existing=False)  # every trace as tiles on the cluster's workers


def run(args: argparse.Namespace) -> int:
    from lenslab.lenses import Camera
    from lenslab.validate import report as report_mod
    from lenslab.validate.run import ValidationError, WarpSetting, parse_size, validate
    from tracer.validate.source import make_source

    from lenslab.errors import UsageError
    from lenslab.jobs.policy import check_output, check_output_dir
    from lenslab.jobs.warp.cameras import given_pose

    if args.look_at is not None and given_pose(args):  # (which of the two to drop cannot be told)
        raise UsageError("give either --look-at or --yaw/--pitch/--roll, not both")
    if args.reference:  # the user's own render or photograph (tracer.validate.reference)
        from tracer.validate.reference import run_reference

        return run_reference(args)
    if args.reference_camera or args.source or args.source_spec:
        raise UsageError("--reference-camera, --source and --from go with --reference FILE")
    size = args.size
    pano_sizes = [parse_size(s) for s in args.pano_sizes.split(",") if s.strip()]
    if not pano_sizes:
        raise UsageError("--pano-sizes is empty; give e.g. 1024x512,2048x1024")
    try:
        settings = [WarpSetting.parse(s) for s in args.filters.split(",") if s.strip()]
    except ValidationError as exc:  # a bad --filters value: a usage error
        raise UsageError(str(exc)) from None
    if not settings:
        raise UsageError("--filters is empty; give e.g. bilinear,antialias,lanczos")
    if args.scene not in ("analytic", "analytic-sky"):  # a scene name known to be none: before any render
        from tracer.load import check_scene_argument

        check_scene_argument(args.scene)
    Camera.from_spec(args.to, size)  # a bad lens spec is a usage error, before anything is rendered
    _refuse_mirrored_target(args.to)
    check_output_dir(args.output)
    if Path(args.output).is_dir():
        for name in REPORT_FILES:
            check_output(Path(args.output) / name, overwrite=args.overwrite)
    analytic = args.scene in ("analytic", "analytic-sky")
    noise_free = bool(args.noise_free) or analytic
    progress = not args.quiet and sys.stderr.isatty()

    # the source and the target camera's pose (a tracer scene suggests one in its default view)
    source = make_source(args.scene, args.integrator, args.max_depth, noise_free)
    from tracer.tiles import attach_cluster

    attach_cluster(source, args)  # with --scheduler: the traces run as tiles on the workers, same pixels
    eye, look_at = (0.0, 0.0, 0.0), None
    view = None if analytic else getattr(source.scene, "views", {}).get("default")
    if view is not None:
        eye, look_at = tuple(view.eye), tuple(view.look_at)
    if args.eye is not None:
        eye = args.eye
        if args.look_at is None and look_at is not None:  # keep the view's direction from the new eye
            import numpy as np

            look_at = tuple(np.add(eye, np.subtract(view.look_at, view.eye)))
    if args.look_at is not None:
        look_at = args.look_at
    if given_pose(args) or look_at is None:  # any of --yaw/--pitch/--roll given: the view they turn, from +z
        target = Camera.from_spec(args.to, size, yaw=args.yaw or 0.0, pitch=args.pitch or 0.0, roll=args.roll or 0.0,
                                  eye=eye)
    else:
        target = Camera.from_spec(args.to, size, eye=eye, look_at=look_at)

    spp = args.spp or (1 if noise_free else 16)
    reference_spp = args.reference_spp or (None if args.reference_error is not None else (64 if noise_free else 1024))
    direct_spp = args.direct_spp if args.direct_spp is not None else [1, 4, 16]
    seed = None if noise_free else args.seed

    val = validate(source, target, pano_sizes, settings, spp=spp, reference_spp=reference_spp,
                   reference_error=args.reference_error, seed=seed, direct_spp=direct_spp,
                   repeat=args.repeat, with_flip=not args.no_flip, progress=progress)
    extra, sections = {}, []
    if args.tune is not None:
        from lenslab.validate.tune import tune

        t = tune(val.rows, args.tune)
        extra["tune"] = t
        sections += ["## Tuning", "", "```", t["summary"], "```", ""]
        print(t["summary"])
    if args.amortised:
        from lenslab.validate.amortised import amortised, markdown

        best_aa = next((s for s in settings if s.antialias), settings[0])
        a = amortised(source, pano_sizes[-1], args.amortised_size, best_aa, spp=spp,
                      reference_spp=reference_spp or 64, direct_spp=direct_spp or [1, 4, 16], seed=seed, eye=eye,
                      yaw0=float(target.pose.ypr[0]), pitch=float(target.pose.ypr[1]), progress=progress)
        extra["amortised"] = a
        sections.append(markdown(a))
    out = report_mod.write_report(val, args.output, extra, sections)
    best = min(val.rows, key=lambda r: r["l1"])
    print(f"reference: {val.meta['reference']['spp']} spp in {val.meta['reference']['seconds']:.2f} s; "
          f"best: {best['label']} at {100 * best['l1']:.3f}% relative L1 "
          f"({100 * best.get('l1_interior', float('nan')):.3f}% away from edges)")
    print(f"report written to {out}/report.md")
    return 0


def _refuse_mirrored_target(spec: str) -> None:
    """``--to IMAGE`` of an image that records a mirrored camera (``lenslab warp --flip`` wrote it): the scene's render
    and its warps take the lens of --to, posed by the scene's view or --yaw/--pitch/--roll, and no mirror, so that
    image's view is not the one validated; said in one line (a usage error) rather than validating another view."""
    from lenslab.errors import UsageError
    from lenslab.jobs.warp.cameras import recorded_view

    view = recorded_view(spec)
    if view is not None and view.pose.mirror:
        raise UsageError(f"--to {spec}: records a mirrored camera (mirror {view.pose.mirror}, as warp --flip writes "
                         f"it), and a scene's validation renders no mirrored view; give its lens: --to "
                         f"{view.lens.spec()}")
