"""Convert images between EXR, Radiance HDR, TIFF, PFM, PPM/PGM, JPG and PNG, many at a time; video
clips to one image per frame, and image sequences (or clips) to a clip.

Inputs may be files, directories (every image file in them; --recursive: in sub-folders too, the tree
mirrored under -o) and glob patterns ('renders/*.exr', 'shots/**/*.exr' at any depth; quote them to
let lenslab expand them). Outputs go to -o DIR (created if needed), to -o FILE for a single input, or
next to each input. --to names the format; -o FILE alone says it by its extension (-o p3.png: PNG).
HDR sources written to display formats (PPM/PGM, JPG, PNG, TIFF with --bits) go through a tone curve
first (--tone, --exposure), then the sRGB encoding, or through an OpenColorIO
display transform instead (--display, --view). EXR to EXR keeps each channel's pixel type (half colour
beside a float depth stays half and float), and a 16-bit PNG, PPM/PGM or TIFF input (or a 10- or 12-bit HEIC)
stays 16-bit in PNG, PPM/PGM and TIFF outputs (--bits 8 makes it 8-bit). A photo's camera EXIF (maker,
model, lens, focal length and focal plane, exposure, date; never GPS, the thumbnail or maker notes) goes
with it into JPG, PNG, TIFF and EXR outputs, fitted to the image written (its own size and orientation), so
'lenslab warp copy.exr --from exif' sees the photo's lens; a damaged EXIF is left out with a note.

An existing output is never replaced without --overwrite. Every file is written to a temporary name
and renamed, so an interrupted run leaves no partial file. A failing input is reported with its
reason and the others go on; the exit code is 1 if any failed.

examples:
  lenslab convert forest.exr -o forest.png          (one output file: the format from its extension)
  lenslab convert renders/ --to jpg -o previews/ --tone hable --exposure 1
  lenslab convert 'scans/*.ppm' --to exr --jobs 1
  lenslab convert pano.exr:left --to png -o left.png
  lenslab convert hdris/ --recursive --to hdr -o hdr-copies/
  lenslab convert pano.exr --to png --display Rec.2100-PQ --view 'HDR 1000 nits (Rec.2020)' -o pq.png
  lenslab convert clip.mp4 --to exr -o frames/ --frames 0:48     (frames/clip.000000.exr ...)
  lenslab convert 'frames/*.exr' --to mov -o clip.mov --rate 25
  lenslab convert clip.mp4 -o clip.mkv                 (every frame, re-encoded, at the clip's own rate)
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from lenslab.jobs.arguments import int_in

from lenslab.io.registry import formats, writable

#: every format lenslab writes, from the format plugins (lenslab.io.formats)
FORMATS = writable()
#: containers an image sequence can be written to: the extensions of the video formats
VIDEO = tuple(dict.fromkeys(e.lstrip(".") for f in formats().values() if f.kind == "video" for e in f.extensions))


def check_convert_options(args, files, display) -> None:
    """--tone and --frames where they cannot apply: usage errors (see lenslab.jobs.arguments)."""
    from lenslab.io.registry import get
    from lenslab.jobs.arguments import check_frames_apply, check_tone_applies, typed
    from lenslab.jobs.warp.video import is_video

    given, args.tone = args.tone is not None, args.tone or "hable"
    args.tone_given = given
    if args.frames is not None:
        check_frames_apply(args.frames, [f for f in files if not is_video(f)])
    if args.to in VIDEO:
        linear = [(args.output, f"a {args.transfer.upper()} clip keeps linear light")] if args.transfer != "bt709" else []
    else:
        fmt = get(args.to)  # integer samples asked of a float format (TIFF --bits) hold display codes
        holds = fmt.hdr and not (args.bits and "sample_type" in fmt.write_options)
        codes = " (with --bits 8 or 16, display codes)" if "sample_type" in fmt.write_options else ""
        linear = [(fmt.title, f"it holds linear light{codes}")] if holds else []
    check_tone_applies(typed(args, "tone", "--tone"), given, display, linear)
    if args.to not in VIDEO:
        from lenslab.jobs.display import check_display_outputs

        check_display_outputs(display, [get(args.to)], args.bits)
        if not display:  # a display's codes are RGB, whatever the input
            from lenslab.jobs.stages import check_channels_fit

            for f in files:
                check_channels_fit(f, get(args.to))


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("inputs", nargs="+", metavar="INPUT", help="image files, directories or glob patterns")
    from lenslab.jobs.arguments import OneFormat

    parser.add_argument("--to", "--format", dest="to", choices=FORMATS + VIDEO, metavar="FORMAT", action=OneFormat,
                        help=f"output format: {', '.join(FORMATS)}; or {', '.join(VIDEO)}: every input (every frame of a clip), "
                             "in order, as the frames of one clip (-o FILE). Default: the extension of -o FILE (-o p3.png "
                             "writes PNG); needed with -o DIR or without -o")
    parser.add_argument("-o", "--output", metavar="DIR_OR_FILE",
                        help="output directory (created if missing), or a file name when there is one input; "
                             "default: next to each input")
    from lenslab.jobs.arguments import add_tone_option

    add_tone_option(parser, "tone", default=None,
                    help="tone curve for HDR -> display formats (default: hable; clamp keeps the values "
                         "as they are, clipped to 1); refused for outputs that keep linear light and with "
                         "--display")
    parser.add_argument("--exposure", default="0", metavar="EV",
                        help="exposure in stops applied before the tone curve, or 'auto' (default: 0)")
    parser.add_argument("--overwrite", action="store_true", help="replace existing output files")
    parser.add_argument("--quality", type=int_in(0, 100), default=95, metavar="Q", help="JPG quality 0..100 (default 95)")
    parser.add_argument("--bits", type=int, choices=(8, 16), default=None,
                        help="PNG/PPM/PGM bits per sample (default: 16 for an input of 9 to 16 bits, else 8); TIFF: "
                             "8- or 16-bit display-encoded integers instead of floats (default: 16-bit integers "
                             "for an input of 9 to 16 bits, else floats)")
    from lenslab.jobs.pixel_types import pixel_type_choices

    parser.add_argument("--pixel-type", choices=pixel_type_choices(), default=None,
                        help="the output's samples: half or float for EXR and TIFF colour and alpha (default: each "
                             "channel's stored type for EXR to EXR, else half for EXR, float for TIFF; other EXR "
                             "channels keep theirs); uint8 or uint16 for PNG, PPM and TIFF (as --bits); a type the "
                             "format cannot hold is refused")
    parser.add_argument("--compression", default=None,
                        help="EXR compression (default zip, readable everywhere; also piz, zips, rle, none, "
                             "pxr24, b44, dwaa, dwab, zstd, htj2k256); TIFF: zlib (default), lzw, zstd, none")
    parser.add_argument("--recursive", "-r", action="store_true",
                        help="walk directories into their sub-folders and mirror the tree under -o")
    from lenslab.jobs.warp.video import parse_frames

    parser.add_argument("--frames", metavar="A:B", default=None, type=parse_frames,
                        help="video inputs: only frames A to B-1 (e.g. 10:20), written as NAME.000010.exr, ... "
                             "(or -o 'f_%%04d.exr': f_0010.exr ...); all or none: a failed frame leaves none")
    from lenslab.io.video.codecs import CODECS
    from lenslab.jobs.arguments import float_in

    parser.add_argument("--rate", type=float_in(0, 1000), default=None, metavar="FPS",
                        help="frames per second of a clip (default: the rate of the first input clip, else 24)")
    parser.add_argument("--transfer", choices=("bt709", "pq", "hlg"), default="bt709",
                        help="a clip made from images: bt709 SDR (tone-mapped, default), or pq / hlg HDR "
                             "(BT.2020, 10-bit, linear 1.0 = 203 cd/m2)")
    parser.add_argument("--codec", choices=tuple(CODECS), default=None,
                        help="video codec of a clip (default by extension: .mp4 h264 or h265 for HDR, .mov prores, "
                             ".mkv ffv1)")
    parser.add_argument("--data-window", action="store_true",
                        help="EXR input: keep the stored data window instead of placing it in the display window "
                             "(EXR to EXR always keeps both windows as stored)")
    parser.add_argument("--quiet", "-q", action="store_true", help="no progress bar")
    from lenslab.cli.display import add_display_arguments
    from lenslab.jobs.arguments import add_jobs_option, add_scheduler_options

    add_display_arguments(parser)
    add_jobs_option(parser, "files to convert")
    add_scheduler_options(parser)


def run(args: argparse.Namespace) -> int:
    from lenslab.cli.display import display_options, say_view
    from lenslab.errors import UsageError
    from lenslab.io.registry import get
    from lenslab.jobs.arguments import check_skip_or_overwrite, parse_exposure
    from lenslab.jobs.plan import expand_inputs

    check_skip_or_overwrite(args)
    args.to = args.to or format_from_output(args.output)
    exposure = parse_exposure(args.exposure)
    display = display_options(args)  # bad display names: one usage error before any folder is made
    from lenslab.jobs.pixel_types import check_pixel_type, integer_bits

    check_pixel_type(args.pixel_type, get("video" if args.to in VIDEO else args.to), args.bits)
    if integer_bits(args.pixel_type):  # integers are --bits (a TIFF's, a PNG's depth)
        args.bits, args.pixel_type = integer_bits(args.pixel_type), None
    if args.to not in VIDEO:
        fmt = get(args.to)
        if args.bits and (args.bits not in fmt.bit_depths or not {"bits", "sample_type"} & set(fmt.write_options)):
            raise UsageError(f"--bits {args.bits}: {fmt.title} is not written with {args.bits}-bit integer samples")
        if not fmt.hdr or args.bits:
            from lenslab.tone import get_curve

            get_curve(args.tone or "hable")  # an unknown curve: one usage error, before any folder is made
        check_compression(fmt, args.compression)
    roots: dict[str, str] = {}
    files, missing = expand_inputs(args.inputs, args.recursive, roots)
    from lenslab.jobs.plan import plan_outputs

    # where each output goes: a usage error (an input written over, two inputs to one output) before any read
    pairs = plan_outputs(files, args.output, fmt.extensions[0], roots, fmt=args.to) if files and args.to not in VIDEO else []
    check_convert_options(args, files, display["display"])
    from lenslab.jobs.funnel import report_missing

    report_missing("lenslab convert", missing)
    if not files:
        if not missing:  # each missing input already has its line
            print("lenslab convert: error: nothing to convert", file=sys.stderr)
        return 1
    if args.to in VIDEO:  # every input, in order, as one clip
        from lenslab.jobs.convert_video import files_to_video

        if not args.output or Path(args.output).suffix.lower() != "." + args.to:
            raise UsageError(f"--to {args.to}: name the clip with -o NAME.{args.to}")
        options = {"tone": args.tone, "exposure": exposure, "overwrite": args.overwrite, "rate": args.rate,
                   "transfer": args.transfer, "codec": args.codec, "quiet": args.quiet, "frames": args.frames,
                   **display}
        written = files_to_video(files, args.output, options)  # a clip among the inputs: every frame of it
        if not args.quiet:
            print(f"wrote {written} frame(s) to {args.output}", file=sys.stderr)
        say_view(args.output, display, args.quiet)
        return 1 if missing else 0
    from lenslab.jobs.convert import ConvertJob
    from lenslab.jobs.plan import skip_existing, sweep_outputs
    from lenslab.jobs.runner import connect, run_batch

    job = ConvertJob.from_options(args, exposure=exposure, **display)
    from lenslab.jobs.convert import check_maps_look

    check_maps_look(files, args.to, args.bits, job)  # an ST map given a look: a usage error before any file
    args._client = connect(args)  # an unreachable scheduler: one error, before any folder is made
    if args.output is not None and (len(pairs) > 1 or Path(args.output).suffix == ""):
        from lenslab.jobs.policy import make_output_dir

        make_output_dir(args.output)
        for folder in sorted({Path(dst).parent for _, dst in pairs}):
            folder.mkdir(parents=True, exist_ok=True)  # the mirrored sub-folders
    sweep_outputs(pairs)  # temporaries of killed runs
    pairs, skipped = skip_existing(pairs, args.skip_existing)
    from lenslab.jobs.frame_files import in_sequence_folder
    from lenslab.jobs.warp.video import is_video

    # a clip to 'frames/%04d.png': the folder made as -o DIR is
    status = in_sequence_folder(pairs, is_video, lambda: run_batch(
        "lenslab convert", job, pairs, args, skipped=skipped,
        summary=lambda where: f"converted {{done}} of {{total}} file(s) to {args.to.upper()}{where}"))
    if not status or len(pairs) > 1:  # something was written through the display: its view, once
        say_view(args.output or "lenslab convert", display, args.quiet)
    return 1 if status or missing else 0


def format_from_output(output: str | None) -> str:
    """The format an output file name says (``-o p3.png``: png; ``-o clip.mov``: mov, a clip of every input),
    when ``--to`` is not given; a usage error, before any input is read, when there is no such name (no
    ``-o``, or ``-o`` a folder) or lenslab does not write what it says."""
    from lenslab.errors import UsageError
    from lenslab.jobs.policy import output_format

    if output is None or Path(output).suffix == "" or Path(output).is_dir():
        where = "-o names a folder" if output is not None else "no -o"
        raise UsageError(f"say which format to write: --to FORMAT ({', '.join(FORMATS + VIDEO)}), or -o NAME.EXT "
                         f"for one output file ({where})")
    ext = Path(output).suffix.lower().lstrip(".")
    name = ext if ext in VIDEO else output_format(output)  # an unknown extension: a usage error
    if name not in FORMATS + VIDEO:
        raise UsageError(f"-o {output}: lenslab does not write {name}; give --to FORMAT ({', '.join(FORMATS)})")
    return name


def check_compression(fmt, value: str | None) -> None:
    """``--compression`` must be one the format declares (a usage error before any work); None keeps the
    format's default."""
    from lenslab.errors import UsageError

    if value is None:
        return
    if not fmt.compressions:
        raise UsageError(f"--compression applies to formats that offer a choice, not {fmt.name}")
    if str(value).lower().replace("_compression", "") not in fmt.compressions:
        raise UsageError(f"--compression {value}: choose one of {', '.join(fmt.compressions)}")
