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
once, also when files are warped at once (--jobs); -o is then a directory. A failing input is reported and the others go on; the exit code is 1
if any failed. Outputs are written to a temporary name and renamed.

Shrinking a detailed source (a 4K panorama into a 1K fisheye) aliases with one sample per pixel:
add --antialias (a footprint filter: as accurate as 4x4 supersampling or better, at about half its
cost) or --samples 16. --antialias averages each output pixel's whole area, so it softens a view
that does not shrink the source (a same-size or enlarged warp: each pixel then takes 9/16 of the
source pixel under it and the rest from its neighbours, as dense supersampling does); use it where
the output shrinks the source. A warp given --antialias that shrinks the source nowhere says so.

examples:
  lenslab warp pano.exr -o fish.exr --to fisheye:fov=180 --size 1024x1024 --antialias
  lenslab warp pano.exr -o view.jpg --to perspective:fov=70 --size 1280x720 --yaw 30 --pitch -10
  lenslab warp 'frames/*.exr' -o fisheye/ --to fisheye:fov=200,mapping=equisolid --size 2048x2048
  lenslab warp fish.exr -o pano.exr --to equirect --size 4096x2048      (the camera comes from fish.exr)
  lenslab warp IMG_0042.jpg -o pano.exr --from exif --to equirect     (a phone photo's own field of view)
  lenslab warp plate.exr -o undistorted.exr --stmap undistort.exr --filter bicubic --samples 4
  lenslab warp clip.mp4 -o fish.mp4 --to fisheye:fov=180 --size 1080x1080 --frames 0:240
      (video: every frame with one map; rate, colour tags and audio kept; PQ/HLG stay HDR)
  lenslab warp clip.mp4 -o 'fish/%04d.exr' --to fisheye:fov=180 --size 1080x1080
      (one image per frame, numbered as in the clip: fish/0000.exr ...; -o fish/shot.exr: shot.000000.exr ...)
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from lenslab.jobs.arguments import Once, finite_float, finite_vector, image_size, int_in, non_empty

from lenslab.io.registry import writable

#: every format lenslab writes, from the format plugins (lenslab.io.formats)
OUTPUT_FORMATS = writable()
#: samples per output pixel: beyond this a warp takes hours and gains nothing a footprint filter
#: (--antialias) does not give at once
MAX_SAMPLES = 4096



def _autoscale_mode(value: str) -> str:
    """--autoscale's MODE; a word that is no mode is refused, and one that names a file (the input, given after an
    --autoscale put before the inputs) says where --autoscale goes."""
    import argparse
    import os

    if value in ("fill", "cover"):
        return value
    hint = ("; --autoscale takes an optional MODE, so it took the next word: put --autoscale after the input files"
            if os.path.sep in value or "." in value or os.path.exists(value) else "")
    raise argparse.ArgumentTypeError(f"invalid choice: {value!r} (choose from 'fill', 'cover'){hint}")

def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("inputs", nargs="+", metavar="IN", help="image files, directories or glob patterns")
    parser.add_argument("-o", "--output", required=True, metavar="OUT",
                        help="output file (one input; a clip to images: 'frames/%%04d.png' or frames/NAME.png, one "
                             "file per frame), or directory (created if missing)")
    parser.add_argument("--to", metavar="SPEC", action=Once,
                        help="output lens, e.g. fisheye:fov=180, perspective:fov=90, equirect, cubemap, "
                             "tiled:2x2,tiles=cams.toml (see 'lenslab lenses'), a calibration file; or an image that "
                             "records its camera (an EXR of 'tracer render'): the same view as that image, its lens, "
                             "orientation, size and eye (a source that records its camera at another eye is "
                             "refused for parallax), so "
                             "--yaw/--pitch/--roll/--look-at are refused with it; or give --stmap")
    parser.add_argument("--stmap", metavar="MAP",
                        help="warp by an ST map from any tool instead of lenses (Nuke's STMap convention: "
                             "R = x/W, G = 1 - y/H of the source position, A = validity; the output takes "
                             "the map's size; --filter, --samples and --antialias apply; a photo turned by its "
                             "EXIF orientation is read as stored when a lenslab map was made for that size; "
                             "see 'lenslab stmap')")
    parser.add_argument("--from", dest="source", metavar="SPEC", action=Once, type=non_empty,
                        help="source lens; default: the camera stored in the file, else equirect when the "
                             "image is twice as wide as tall. 'exif': a phone or camera photo's own lens, the "
                             "pinhole (perspective) of its EXIF 35 mm equivalent focal length, by the diagonal, for "
                             "the photo as shown (after its EXIF orientation; 'lenslab info PHOTO' prints it); "
                             "'lensfun:auto': the lens its metadata names, with its distortion, from lensfun")
    parser.add_argument("--size", metavar="WxH", type=image_size,
                        help="output size in pixels; default: the source's angular resolution in the output lens's "
                             "own shape, its field at the pixels per degree the source has (an equirect's rows over 180 degrees, "
                             "a cube map's faces or a grid's tiles over 90, an eye's of a stereo frame, a perspective "
                             "view's rows over its vertical field; along its middle row where that is coarser, as a cylindrical panorama's 360 degrees): a 180-degree fisheye as many rows as 180 degrees of "
                             "the source, a 90-degree fisheye or perspective view half as many; square for a fisheye or "
                             "perspective view, a lensfun lens's calibration sensor's shape (3:2, 4:3), 2:1 for a whole equirect (square pixels over its ranges for part of one); a cube map: square faces of 90 degrees, 3:2 for a 3x2 "
                             "cube map; a tiled grid: square tiles, a 90-degree tile half those rows; each eye of a stereo frame; a camera file: the size it was calibrated at; never "
                             "more than twice the source's pixels, an eye of a stereo frame (a note then gives the size "
                             "that keeps them)")
    pose = parser.add_argument_group("output camera pose (degrees, world frame: +z forward, +y up)")
    pose.add_argument("--yaw", type=finite_float, help="turn right about the up axis (default 0)")
    pose.add_argument("--pitch", type=finite_float, help="turn up (default 0)")
    pose.add_argument("--roll", type=finite_float, help="turn about the viewing axis (default 0)")
    pose.add_argument("--rotation-order", choices=("ypr", "yrp", "pyr", "pry", "ryp", "rpy"), default=None,
                      metavar="ORDER", help="the order of the turns, last applied first: ypr (default) turns roll, "
                                            "then pitch, then yaw; ffmpeg v360's rorder; only with --yaw/--pitch/--roll")
    pose.add_argument("--flip", metavar="h,v,d", default=None,
                      help="mirror the output's rays: h left-right, v up-down, d front-back (v360's h_flip, "
                           "v_flip, d_flip); not with --to IMAGE, whose view is the file's")
    pose.add_argument("--source-flip", metavar="h,v", default=None,
                      help="the source was stored mirrored left-right (h) and/or top-bottom (v) within each "
                           "face, half or eye (v360's ih_flip, iv_flip)")
    pose.add_argument("--look-at", metavar="X,Y,Z", type=finite_vector,
                      help="look along this direction instead of --yaw/--pitch/--roll, e.g. 0,1,0 straight up")
    pose.add_argument("--eye", metavar="X,Y,Z", default=None, type=finite_vector,
                      help="output eye point (default: the source's); another point needs --allow-parallax")
    quality = parser.add_argument_group("sampling")
    from lenslab.filters import FILTERS, cli_filter

    quality.add_argument("--filter", choices=list(FILTERS), type=cli_filter, default="bilinear",
                         help="reconstruction filter (default bilinear): "
                              + "; ".join(f"{e.name}, {e.summary}" for e in FILTERS.entries()))
    quality.add_argument("--samples", type=int_in(1, MAX_SAMPLES), default=1, metavar="N",
                         help=f"stratified samples per output pixel (e.g. 4, 16; default 1, at most {MAX_SAMPLES})")
    quality.add_argument("--seed", type=int, default=None,
                         help="jitter the samples within their strata with this seed (default: strata centres)")
    quality.add_argument("--antialias", action="store_true",
                         help="average each output pixel's whole area (a footprint filter, bilinear, mip levels): "
                              "for views that shrink the source; it softens a same-size or enlarged view (a note "
                              "says so). It replaces --filter, so the two are not given together")
    quality.add_argument("--exact-map", action="store_true",
                         help="evaluate the lens models at every sample (default: a checked interpolation "
                              "lattice, within 1/100 pixel)")
    out = parser.add_argument_group("output")
    out.add_argument("--format", choices=OUTPUT_FORMATS, default=None,
                     help="output format when -o is a directory (default exr), else from the file name")
    from lenslab.jobs.arguments import add_tone_option

    add_tone_option(out, "tone", default=None,
                    help="tone curve for HDR input written to PNG/JPG/PPM (default hable); refused with an "
                         "output that keeps linear light (EXR, TIFF, PFM, HDR, video) and with --display "
                         "(a display transform maps scene light itself)")
    out.add_argument("--exposure", default="0", metavar="EV", help="exposure in stops before the curve, or 'auto'")
    from lenslab.jobs.pixel_types import pixel_type_choices

    out.add_argument("--pixel-type", choices=pixel_type_choices(), default=None,
                     help="the output's samples: half or float (EXR, default half; TIFF, default float), uint8 or "
                          "uint16 (PNG, PPM, TIFF; default uint8); a type the format cannot hold is refused")
    out.add_argument("--no-alpha", action="store_true", help="do not write the alpha channel")
    out.add_argument("--overwrite", action="store_true", help="replace existing output files")
    parser.add_argument("--allow-parallax", action="store_true",
                        help="warp views whose eye differs from the source's anyway (warns: parallax is not "
                             "reproduced)")
    parser.add_argument("--autoscale", nargs="?", const="fill", type=_autoscale_mode, default=None,
                        metavar="MODE",
                        help="scale the output lens's field of view: 'fill' (the default mode) takes the widest "
                             "field with no empty pixel, 'cover' the narrowest that shows all of the source; "
                             "put it after the input files; not with --to IMAGE, whose view is the file's")
    parser.add_argument("--compat", choices=("v360",), default=None,
                        help="map pixels as ffmpeg's v360 filter does (how it reads each projection, no pole "
                             "continuation, one sample per pixel; docs/v360.md lists the projections and options "
                             "both share), to match footage converted with it")
    parser.add_argument("--quiet", "-q", action="store_true", help="no progress bar and no summary")
    parser.add_argument("--verbose", "-v", action="store_true",
                        help="also print how --autoscale searched (scale, evaluations, the optimiser's check)")
    from lenslab.jobs.arguments import add_jobs_option, add_scheduler_options
    from lenslab.cli.display import add_display_arguments
    from lenslab.jobs.warp.video import add_video_arguments

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
    the tone curve for display outputs, the display."""
    from lenslab.jobs.warp.cameras import check_turn_order, check_view_pose, default_size, given_pose, note_size
    from lenslab.lenses.registry import make_lens

    if args.to:
        note_size(make_lens(args.to, args.size or default_size(args.to, 256)))  # (the default size has no note)
        check_view_pose(args.to, given_pose(args, "--yaw", "--pitch", "--roll", "--look-at", "--rotation-order",
                                            "--flip", "--autoscale"))
    check_turn_order(args)
    from lenslab.lenses.spec_kinds import exif_photo, is_auto, is_exif

    if args.source and not is_auto(args.source) and not (is_exif(args.source) and exif_photo(args.source) is None):
        # auto and exif: read from each input's metadata
        make_lens(args.source, (512, 256))
    if args.tone:  # the default curve (hable) needs no check, nor the curves loaded
        from lenslab.tone import get_curve

        get_curve(args.tone)
    from lenslab.cli.display import display_options

    display_options(args)  # unknown display, view or colour space: one usage error now


def check_options_apply(args, pairs) -> None:
    """Options that cannot apply to these inputs and outputs are usage errors, never silently ignored."""
    from lenslab.io.registry import get
    from lenslab.jobs.policy import output_format  # a name lenslab does not write: a usage error
    from lenslab.jobs.arguments import check_frames_apply, check_tone_applies, typed
    from lenslab.jobs.warp.video import is_video

    tone_given, args.tone = args.tone is not None, args.tone or "hable"
    args.tone_given = tone_given
    videos = [is_video(src) for src, _ in pairs]
    check_video_output(pairs, videos)
    if getattr(args, "frames", None) is not None:
        check_frames_apply(args.frames, [src for (src, _), v in zip(pairs, videos) if not v])
    from lenslab.jobs.warp.video import image_format

    # a clip to a clip (or to a name the warp refuses); a clip to image files is developed as still images are
    clips = [v and image_format(dst) is None for (_, dst), v in zip(pairs, videos)]
    from lenslab.jobs.pixel_types import check_pixel_type, integer_bits

    for (_, dst), v in zip(pairs, clips):  # a type the output cannot hold: one line, before any file is read
        check_pixel_type(args.pixel_type, get("video" if v else output_format(dst)))
    codes = integer_bits(args.pixel_type)  # a TIFF of integer samples holds display codes, as a PNG does
    linear = [(dst, "a video keeps linear light through its transfer") if v
              else (dst, f"{get(output_format(dst)).title} holds linear light")
              for (_, dst), v in zip(pairs, clips) if v or (get(output_format(dst)).hdr and not codes)]
    check_tone_applies(typed(args, "tone", "--tone"), tone_given, getattr(args, "display", None), linear)
    from lenslab.jobs.display import check_display_outputs
    from lenslab.jobs.stages import check_channels_fit

    # from the names, before any header is read for its channels
    check_display_outputs(getattr(args, "display", None),
                          [get(name) for name in {output_format(dst) for (_, dst), v in zip(pairs, clips) if not v}])
    for (src, dst), video in zip(pairs, videos):
        if not video and not getattr(args, "display", None):  # a display's codes are RGB, whatever the input
            check_channels_fit(src, get(output_format(dst)))


def check_video_output(pairs, videos) -> None:
    """A video output needs a video input: an input lenslab cannot read is named as the cause (a failed
    input), a still image is a usage error; never "cannot tell the output format" of a good output name."""
    from lenslab.errors import UsageError
    from lenslab.io import split_selector
    from lenslab.io.video.codecs import VIDEO_EXTENSIONS
    from lenslab.io.registry import sniff

    for (src, dst), video in zip(pairs, videos):
        if not video and Path(dst).suffix.lower() in VIDEO_EXTENSIONS:
            from lenslab.jobs.funnel import working_on

            with working_on(src):
                sniff(split_selector(src)[0])  # an input it cannot read: its own error, naming it
            raise UsageError(f"{src} is a still image and -o {dst} a video: warp it to an image file "
                             "(e.g. .exr), or give a video input")


def output_extension(fmt: str | None):
    """The extension of each output in an -o folder: ``--format``'s (default EXR); a clip stays a clip."""
    from lenslab.io.registry import get
    from lenslab.jobs.warp.video import is_video

    ext = get(fmt or "exr").extensions[0]
    return lambda src: src.suffix.lower() if fmt is None and is_video(src) else ext


def check_compat(args: argparse.Namespace) -> None:
    """``--compat v360``'s conditions that depend on no file, once before any work (a usage error): one
    sample per pixel, and lenses that v360 has (``--to``, and ``--from`` when it is a lens spec)."""
    from lenslab.errors import LenslabError, UsageError
    from lenslab.lenses import make_lens
    from lenslab.warp.compat_v360 import check_v360

    def lens(spec):
        if not spec or spec.strip().lower() in ("auto", "exif") or spec.lower().startswith("lensfun:auto"):
            return None
        try:
            return make_lens(spec, (64, 32))
        except LenslabError:  # a camera file, or a spec the warp itself reports
            return None

    try:
        check_v360(lens(args.source), lens(args.to), args.samples, args.antialias)
    except LenslabError as exc:
        raise UsageError(str(exc)) from None


def run(args: argparse.Namespace) -> int:
    from lenslab.errors import LenslabError, UsageError
    from lenslab.jobs.arguments import check_skip_or_overwrite, parse_exposure
    from lenslab.jobs.plan import expand_inputs, plan_outputs, skip_existing, sweep_outputs
    from lenslab.jobs.runner import connect, run_batch
    from lenslab.jobs.warp import WarpJob, plans_for, st_map
    from lenslab.jobs.warp.cameras import given_pose

    check_skip_or_overwrite(args)
    if args.look_at is not None and given_pose(args):
        raise UsageError("give either --look-at or --yaw/--pitch/--roll, not both")
    from lenslab.warp.mirror import parse_flips

    try:  # bad letters are a usage error, before any file is read
        parse_flips(args.flip)
        parse_flips(args.source_flip, "hv", "--source-flip")
    except LenslabError as exc:
        raise UsageError(str(exc)) from None
    if args.look_at and not any(args.look_at):
        raise UsageError("--look-at 0,0,0 is no direction; give X,Y,Z with a length, e.g. 0,0,1")
    if not args.to and not args.stmap:
        raise UsageError("say where to warp to: --to SPEC (the output lens) or --stmap MAP")
    if args.stmap:
        taken = [flag for flag, on in (("--to", args.to), ("--from", args.source), ("--size", args.size),
                                        ("--compat", args.compat), ("--flip", args.flip),
                                        ("--source-flip", args.source_flip),
                                        ("--rotation-order", args.rotation_order),
                                        ("--autoscale", args.autoscale), ("--look-at", args.look_at),
                                        ("--eye", args.eye), ("--yaw/--pitch/--roll", given_pose(args)))
                 if on]
        if taken:
            raise UsageError(f"--stmap gives the whole geometry; drop {', '.join(taken)}")
        if args.antialias and args.samples != 1:
            raise UsageError("with an ST map, give either --antialias or --samples, not both")
        st_map(args.stmap)  # read now: a bad map is one error before any file
    from lenslab.filters import check_filter_with_antialias

    try:
        check_filter_with_antialias(args.filter, args.antialias, ("--filter", "--antialias"))
    except LenslabError as exc:
        raise UsageError(str(exc)) from None
    args.exposure = parse_exposure(args.exposure)
    check_once(args)
    if args.compat:
        check_compat(args)
    files, missing = expand_inputs(args.inputs)
    from lenslab.jobs.funnel import report_missing

    report_missing("lenslab warp", missing)
    if not files:
        if not missing:
            print("lenslab warp: error: nothing to warp", file=sys.stderr)
        return 1
    pairs = plan_outputs(files, args.output, output_extension(args.format), fmt=args.format, verb="warp")
    if args.stmap:  # the map is an input too: named as an output, a usage error before any image is read
        from lenslab.jobs.policy import refuse_inputs

        refuse_inputs([dst for _, dst in pairs], [args.stmap])
    check_options_apply(args, pairs)
    from lenslab.jobs.warp.video import is_video

    if args.size and not args.autoscale:  # a size a clip's encoder refuses: a usage error before any frame
        from lenslab.io.video.codecs import VIDEO_EXTENSIONS, check_clip_size

        for src, dst in pairs:
            if Path(dst).suffix.lower() in VIDEO_EXTENSIONS and is_video(src):
                check_clip_size(tuple(args.size), dst, args.codec)

    # one still image: no later image reuses its maps, which are then not kept
    job = WarpJob.from_options(args, keep_maps=len(pairs) > 1 or any(is_video(src) for src, _ in pairs))
    args._client = connect(args)  # an unreachable scheduler: one error, before any folder is made
    if len(pairs) > 1 or Path(args.output).suffix == "":
        from lenslab.jobs.policy import make_output_dir

        make_output_dir(args.output)
    sweep_outputs(pairs)  # temporaries of killed runs
    pairs, skipped = skip_existing(pairs, args.skip_existing)

    def summary(where: str) -> str:
        maps = "" if where else f" by the ST map {args.stmap}" if args.stmap else f" with {plans_for(job).built} map(s)"
        return f"warped {{done}} of {{total}} file(s){maps}{where}"

    from lenslab.jobs.frame_files import in_sequence_folder

    # a clip to 'frames/%04d.png': the folder made as -o DIR is
    status = in_sequence_folder(pairs, is_video, lambda: run_batch("lenslab warp", job, pairs, args, summary, skipped))
    if not status or len(pairs) > 1:  # something was written through the display: its view, once
        from lenslab.cli.display import display_options, say_view

        say_view(args.output or "lenslab warp", display_options(args), args.quiet)
    return 1 if status or missing else 0
