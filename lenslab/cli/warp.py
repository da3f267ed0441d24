"""Reproject images from one lens into another: HDR in, HDR out, anti-aliased, with alpha.

Each output pixel looks along its ray(s) of the output camera (--to, --size, --yaw/--pitch/--roll or
--look-at) and reads the source image where the source camera (--from) sees that direction. Values
are never clamped; the output's alpha is the coverage (the fraction of the pixel's samples that land
on the source), written as the A channel of every format that holds alpha (EXR, PNG, TIFF), with the
colour as that format keeps it: premultiplied in EXR and float TIFF, straight in PNG and 8/16-bit TIFF.
EXR output records the output camera in its header, so it can be warped again.

The source camera comes from --from, else from the file's own header (EXR written by lenslab), else
a full equirect panorama is assumed when the image is twice as wide as it is tall.

Several inputs (files, directories or glob patterns) with one geometry share one map, computed
once; -o is then a directory. A failing input is reported and the others go on; the exit code is 1
if any failed. Outputs are written to a temporary name and renamed.

Shrinking a detailed source (a 4K panorama into a 1K fisheye) aliases with one sample per pixel:
add --antialias (a footprint filter: as accurate as 4x4 supersampling or better, at about half its
cost) or --samples 16.

examples:
  lenslab warp pano.exr -o fish.exr --to fisheye:fov=180 --size 1024x1024 --antialias
  lenslab warp pano.exr -o view.jpg --to perspective:fov=70 --size 1280x720 --yaw 30 --pitch -10
  lenslab warp 'frames/*.exr' -o fisheye/ --to fisheye:fov=200,mapping=equisolid --size 2048x2048
  lenslab warp fish.exr -o pano.exr --to equirect --size 4096x2048      (the camera comes from fish.exr)
  lenslab warp plate.exr -o undistorted.exr --stmap undistort.exr --filter bicubic --samples 4
  lenslab warp clip.mp4 -o fish.mp4 --to fisheye:fov=180 --size 1080x1080 --frames 0:240
      (video: every frame with one map; rate, colour tags and audio kept; PQ/HLG stay HDR)
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from lenslab.cli.options import Once
from lenslab.cli.policy import image_size, positive_int

from lenslab.io.registry import writable

#: every format lenslab writes, from the format plugins (lenslab.io.formats)
OUTPUT_FORMATS = writable()


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("inputs", nargs="+", metavar="IN", help="image files, directories or glob patterns")
    parser.add_argument("-o", "--output", required=True, metavar="OUT",
                        help="output file (one input), or directory (created if missing)")
    parser.add_argument("--to", metavar="SPEC", action=Once,
                        help="output lens, e.g. fisheye:fov=180, perspective:fov=90, equirect, cubemap, "
                             "tiled:2x2,tiles=cams.toml (see 'lenslab lenses'); or give --stmap")
    parser.add_argument("--stmap", metavar="MAP",
                        help="warp by an ST map from any tool instead of lenses (Nuke's STMap convention: "
                             "R = x/W, G = 1 - y/H of the source position, A = validity; the output takes "
                             "the map's size; --filter, --samples and --antialias apply; see 'lenslab stmap')")
    parser.add_argument("--from", dest="source", metavar="SPEC", action=Once,
                        help="source lens; default: the camera stored in the file, else equirect when the "
                             "image is twice as wide as tall")
    parser.add_argument("--size", metavar="WxH", type=image_size,
                        help="output size in pixels; default: the source's height squared (2:1 for equirect)")
    pose = parser.add_argument_group("output camera pose (degrees, world frame: +z forward, +y up)")
    pose.add_argument("--yaw", type=float, default=0.0, help="turn right about the up axis")
    pose.add_argument("--pitch", type=float, default=0.0, help="turn up")
    pose.add_argument("--roll", type=float, default=0.0, help="turn about the viewing axis")
    pose.add_argument("--look-at", metavar="X,Y,Z",
                      help="look along this direction instead of --yaw/--pitch/--roll, e.g. 0,1,0 straight up")
    pose.add_argument("--eye", metavar="X,Y,Z", default=None,
                      help="output eye point (default: the source's); another point needs --allow-parallax")
    quality = parser.add_argument_group("sampling")
    quality.add_argument("--filter", choices=("nearest", "bilinear", "bicubic", "lanczos"), default="bilinear",
                         help="reconstruction filter (default bilinear; bicubic = Catmull-Rom, lanczos = Lanczos-3)")
    quality.add_argument("--samples", type=positive_int, default=1, metavar="N",
                         help="stratified samples per output pixel (e.g. 4, 16; default 1)")
    quality.add_argument("--seed", type=int, default=None,
                         help="jitter the samples within their strata with this seed (default: strata centres)")
    quality.add_argument("--antialias", action="store_true",
                         help="footprint prefilter where the output shrinks the source (bilinear, mip levels)")
    quality.add_argument("--exact-map", action="store_true",
                         help="evaluate the lens models at every sample (default: a checked interpolation "
                              "lattice, within 1/100 pixel)")
    out = parser.add_argument_group("output")
    out.add_argument("--format", choices=OUTPUT_FORMATS, default=None,
                     help="output format when -o is a directory (default exr), else from the file name")
    out.add_argument("--tone", default=None, metavar="CURVE",
                     help="tone curve for HDR input written to PNG/JPG/PPM (default hable); refused with an "
                          "output that keeps linear light (EXR, TIFF, PFM, HDR, video) and with --display "
                          "(a display transform maps scene light itself)")
    out.add_argument("--exposure", default="0", metavar="EV", help="exposure in stops before the curve, or 'auto'")
    out.add_argument("--pixel-type", choices=("half", "float"), default="half", help="EXR sample type (default half)")
    out.add_argument("--no-alpha", action="store_true", help="do not write the alpha channel")
    out.add_argument("--overwrite", action="store_true", help="replace existing output files")
    parser.add_argument("--allow-parallax", action="store_true",
                        help="warp views whose eye differs from the source's anyway (warns: parallax is not "
                             "reproduced)")
    parser.add_argument("--autoscale", nargs="?", const="fill", choices=("fill", "cover"), default=None,
                        metavar="MODE",
                        help="scale the output lens's field of view: 'fill' (the default mode) takes the widest "
                             "field with no empty pixel, 'cover' the narrowest that shows all of the source; "
                             "put it after the input files")
    parser.add_argument("--compat", choices=("v360",), default=None,
                        help="map pixels as ffmpeg's v360 filter does (how it reads each projection, no pole "
                             "continuation, one sample per pixel; docs/v360.md lists the projections and options "
                             "both share), to match footage converted with it")
    parser.add_argument("--quiet", "-q", action="store_true", help="no progress bar and no summary")
    parser.add_argument("--verbose", "-v", action="store_true",
                        help="also print how --autoscale searched (scale, evaluations, the optimiser's check)")
    from lenslab.cli.options import add_jobs_option, add_scheduler_options
    from lenslab.cli.display import add_display_arguments
    from lenslab.cli.warp_video import add_video_arguments

    add_display_arguments(parser)
    add_video_arguments(parser)
    add_jobs_option(parser, "files to warp")
    add_scheduler_options(parser)


def parse_size(text: str) -> tuple[int, int]:
    from lenslab.errors import WarpError

    w, sep, h = str(text).lower().partition("x")
    try:
        size = int(w), int(h)
    except ValueError:
        size = (0, 0)
    if not sep or size[0] < 1 or size[1] < 1:
        raise WarpError(f"--size {text!r} must be WIDTHxHEIGHT in pixels, e.g. 1024x1024")
    return size


def check_once(args) -> None:
    """What does not depend on one input, checked before any file is read or folder made: the lenses,
    the tone curve for display outputs."""
    from lenslab.cli.warp_cameras import default_size
    from lenslab.lenses.registry import make_lens
    from lenslab.tone import get_curve

    if args.to:
        make_lens(args.to, args.size or default_size(args.to, 256))
    if args.source:
        make_lens(args.source, (512, 256))
    get_curve(args.tone or "hable")
    from lenslab.cli.display import display_options

    display_options(args)  # unknown display, view or colour space: one usage error now


def check_options_apply(args, pairs) -> None:
    """Options that cannot apply to these inputs and outputs are usage errors, never silently ignored."""
    from lenslab.cli.options import check_frames_apply, check_tone_applies
    from lenslab.cli.warp_video import is_video
    from lenslab.io.registry import format_for_path, get

    tone_given, args.tone = args.tone is not None, args.tone or "hable"
    videos = [is_video(src) for src, _ in pairs]
    if getattr(args, "frames", None) is not None:
        check_frames_apply(args.frames, [src for (src, _), v in zip(pairs, videos) if not v])
    linear = [(dst, "a video keeps linear light through its transfer") if v
              else (dst, f"{get(format_for_path(dst, None)).title} holds linear light")
              for (_, dst), v in zip(pairs, videos) if v or get(format_for_path(dst, None)).hdr]
    check_tone_applies("--tone", tone_given, getattr(args, "display", None), linear)


def plan_outputs(files: list[str], output: str, fmt: str | None) -> list[tuple[str, Path]]:
    from lenslab.cli.policy import check_output_dir
    from lenslab.errors import FormatError
    from lenslab.io import split_selector

    out = Path(output)
    as_file = len(files) == 1 and not out.is_dir() and out.suffix != ""
    if not as_file:
        check_output_dir(out, len(files))  # created by run() once everything is checked
    ext = "." + (fmt or "exr")
    pairs, seen = [], {}
    for f in files:
        src, selector = split_selector(f)
        from lenslab.cli.warp_video import is_video

        own = src.suffix.lower() if fmt is None and is_video(src) else ext  # a clip stays a clip
        dst = out if as_file else out / (src.stem + (f"_{selector.replace(':', '_')}" if selector else "") + own)
        if dst in seen:
            raise FormatError(f"{f} and {seen[dst]} would both be written to {dst}; warp them separately")
        seen[dst] = f
        pairs.append((f, dst))
    return pairs


def run(args: argparse.Namespace) -> int:
    from tqdm import tqdm

    from lenslab.cli.options import check_skip_or_overwrite

    check_skip_or_overwrite(args)

    from lenslab.cli.convert import expand_inputs
    from lenslab.cli.warp_file import plan_cache, warp_one
    from lenslab.cli.policy import UsageError, make_output_dir, one_line, user_notes
    from lenslab.cluster.threads import default_jobs, recorded_warnings, run_threads
    from lenslab.errors import LenslabError

    if args.look_at and (args.yaw or args.pitch or args.roll):
        raise UsageError("give either --look-at or --yaw/--pitch/--roll, not both")
    if not args.to and not args.stmap:
        raise UsageError("say where to warp to: --to SPEC (the output lens) or --stmap MAP")
    if args.stmap:
        taken = [flag for flag, on in (("--to", args.to), ("--from", args.source), ("--size", args.size),
                                        ("--compat", args.compat),
                                        ("--autoscale", args.autoscale), ("--look-at", args.look_at),
                                        ("--eye", args.eye), ("--yaw/--pitch/--roll", args.yaw or args.pitch or args.roll))
                 if on]
        if taken:
            raise UsageError(f"--stmap gives the whole geometry; drop {', '.join(taken)}")
        from lenslab.stmap import read_st_map

        args.st = read_st_map(args.stmap)
    from lenslab.cli.options import parse_exposure

    args.exposure = parse_exposure(args.exposure)
    check_once(args)
    files, missing = expand_inputs(args.inputs)
    for pat, reason in missing:
        print(f"lenslab warp: {pat}: {reason}", file=sys.stderr)
    if not files:
        print("lenslab warp: error: nothing to warp", file=sys.stderr)
        return 1
    pairs = plan_outputs(files, args.output, args.format)
    check_options_apply(args, pairs)
    from lenslab.cluster.command import batch_on_cluster, connect

    client = connect(args)  # an unreachable scheduler: one error, before any folder is made
    if len(pairs) > 1 or Path(args.output).suffix == "":
        make_output_dir(args.output)
    from lenslab.cluster.run import skip_existing

    pairs, skipped = skip_existing(pairs, args.skip_existing)
    if skipped and not args.quiet:
        print(f"lenslab warp: {skipped} output(s) already there, left alone (--skip-existing)", file=sys.stderr)
    if client is not None:
        from lenslab.cluster.tasks import plain_options

        status = batch_on_cluster("lenslab warp", client, "warp_task", pairs,
                                  plain_options(args, paths=("source", "to", "stmap")), args.quiet, "warped")
        return 1 if status or missing else 0
    cache = plan_cache(args)
    show = not args.quiet and sys.stderr.isatty()
    failed = []
    bar = tqdm(total=len(pairs), unit="img", disable=not show or len(pairs) == 1, file=sys.stderr, leave=False)

    def one(pair):
        src_path, dst_path = pair
        rows = None
        if show and len(pairs) == 1:
            rows = tqdm(unit="row", file=sys.stderr, leave=False, desc=os.path.basename(src_path))
        with recorded_warnings() as caught:
            try:
                warp_one(src_path, dst_path, args, cache, progress=rows.update if rows is not None else None)
                error = None
            except (LenslabError, OSError, UsageError) as exc:
                error = one_line(exc)
            except Exception as exc:  # one bad file must not stop the batch
                error = f"{type(exc).__name__}: {exc}"
            finally:
                if rows is not None:
                    rows.close()
        return src_path, error, user_notes(caught)

    def done(result):
        src_path, error, notes = result
        for note in notes:
            print(f"lenslab warp: note: {src_path}: {note}", file=sys.stderr)
        if error:
            failed.append(src_path)
            print(f"lenslab warp: FAILED: {error if src_path in error else f'{src_path}: {error}'}", file=sys.stderr)
        bar.update()

    # the first file alone, on every core: it makes the map the others reuse (a batch has one geometry)
    run_threads(one, pairs, args.jobs or default_jobs(len(pairs) - 1), done, first_alone=True,
                fit_memory=not args.jobs)
    bar.close()
    if not args.quiet:
        done = len(pairs) - len(failed)
        print(f"warped {done} of {len(pairs) + skipped} file(s) with {cache.built} map(s)"
              + (f"; {len(failed)} failed" if failed else "")
              + (f"; {skipped} already there, left alone" if skipped else ""), file=sys.stderr)
    return 1 if failed or missing else 0
