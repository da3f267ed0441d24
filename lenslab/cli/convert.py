"""Convert images between EXR, Radiance HDR, TIFF, PFM, PPM/PGM, JPG and PNG, many at a time; video
clips to one image per frame, and image sequences to a clip.

Inputs may be files, directories (every image file in them; --recursive: in sub-folders too, the tree
mirrored under -o) and glob patterns ('renders/*.exr', 'shots/**/*.exr' at any depth; quote them to
let lenslab expand them). Outputs go to -o DIR (created if needed), to -o FILE for a single input, or
next to each input. HDR sources written to display formats (PPM/PGM, JPG, PNG, TIFF with --bits) go
through a tone curve first (--tone, --exposure), then the sRGB encoding, or through an OpenColorIO
display transform instead (--display, --view). EXR to EXR keeps the input's pixel type.

An existing output is never replaced without --overwrite. Every file is written to a temporary name
and renamed, so an interrupted run leaves no partial file. A failing input is reported with its
reason and the others go on; the exit code is 1 if any failed.

examples:
  lenslab convert renders/ --to jpg -o previews/ --tone hable --exposure 1
  lenslab convert 'scans/*.ppm' --to exr --jobs 1
  lenslab convert pano.exr:left --to png -o left.png
  lenslab convert hdris/ --recursive --to hdr -o hdr-copies/
  lenslab convert pano.exr --to png --display Rec.2100-PQ --view 'HDR 1000 nits (Rec.2020)' -o pq.png
  lenslab convert clip.mp4 --to exr -o frames/ --frames 0:48     (frames/clip.000000.exr ...)
  lenslab convert 'frames/*.exr' --to mov -o clip.mov --rate 25
"""

from __future__ import annotations

import argparse
import glob
import os
import sys
from pathlib import Path

from lenslab.cli.policy import int_in

from lenslab.io.registry import hdr_formats, input_extensions, writable

#: every format lenslab writes, from the format plugins (lenslab.io.formats)
FORMATS = writable()
LDR = tuple(f for f in FORMATS if f not in hdr_formats())
INPUT_EXTENSIONS = input_extensions()
#: containers an image sequence can be written to (see lenslab.io.video)
VIDEO = ("mp4", "mov", "mkv")


def check_convert_options(args, files, display) -> None:
    """--tone and --frames where they cannot apply: usage errors (see lenslab.cli.options)."""
    from lenslab.cli.options import check_frames_apply, check_tone_applies
    from lenslab.cli.warp_video import is_video
    from lenslab.io.registry import get

    given, args.tone = args.tone is not None, args.tone or "hable"
    if args.frames is not None:
        check_frames_apply(args.frames, [f for f in files if not is_video(f)])
    if args.to in VIDEO:
        linear = [(args.output, f"a {args.transfer.upper()} clip keeps linear light")] if args.transfer != "bt709" else []
    else:
        holds = get(args.to).hdr and not (args.to == "tiff" and args.bits)
        linear = [(args.to.upper(), "it holds linear light")] if holds else []
    check_tone_applies("--tone", given, display, linear)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("inputs", nargs="+", metavar="INPUT", help="image files, directories or glob patterns")
    parser.add_argument("--to", required=True, choices=FORMATS + VIDEO, metavar="FORMAT",
                        help=f"output format: {', '.join(FORMATS)}; or {', '.join(VIDEO)}: every input, in order, "
                             "as the frames of one clip (-o FILE)")
    parser.add_argument("-o", "--output", metavar="DIR_OR_FILE",
                        help="output directory (created if missing), or a file name when there is one input; "
                             "default: next to each input")
    parser.add_argument("--tone", default=None, metavar="CURVE",
                        help="tone curve for HDR -> display formats (default: hable; clamp keeps the values "
                             "as they are, clipped to 1); refused for outputs that keep linear light and with "
                             "--display")
    parser.add_argument("--exposure", default="0", metavar="EV",
                        help="exposure in stops applied before the tone curve, or 'auto' (default: 0)")
    parser.add_argument("--overwrite", action="store_true", help="replace existing output files")
    parser.add_argument("--quality", type=int_in(0, 100), default=95, metavar="Q", help="JPG quality 0..100 (default 95)")
    parser.add_argument("--bits", type=int, choices=(8, 16), default=None,
                        help="PNG/PPM/PGM bits per sample (default 8); TIFF: 8- or 16-bit display-encoded "
                             "integers instead of floats")
    parser.add_argument("--pixel-type", choices=("half", "float"), default=None,
                        help="EXR/TIFF float type (default: the input's for EXR to EXR, else half for EXR, "
                             "float for TIFF)")
    parser.add_argument("--compression", default=None,
                        help="EXR compression (default zip, readable everywhere; also piz, zips, rle, none, "
                             "pxr24, b44, dwaa, dwab, zstd, htj2k256); TIFF: zlib (default), lzw, zstd, none")
    parser.add_argument("--recursive", "-r", action="store_true",
                        help="walk directories into their sub-folders and mirror the tree under -o")
    from lenslab.cli.warp_video import parse_frames

    parser.add_argument("--frames", metavar="A:B", default=None, type=parse_frames,
                        help="video inputs: only frames A to B-1 (e.g. 10:20), written as NAME.000010.exr, ...")
    parser.add_argument("--rate", type=float, default=24.0, metavar="FPS",
                        help="frames per second of a clip made from images (default 24)")
    parser.add_argument("--transfer", choices=("bt709", "pq", "hlg"), default="bt709",
                        help="a clip made from images: bt709 SDR (tone-mapped, default), or pq / hlg HDR "
                             "(BT.2020, 10-bit, linear 1.0 = 203 cd/m2)")
    parser.add_argument("--codec", choices=("h264", "h265", "prores", "ffv1"), default=None,
                        help="video codec of a clip (default by extension: .mp4 h264 or h265 for HDR, .mov prores, "
                             ".mkv ffv1)")
    parser.add_argument("--data-window", action="store_true",
                        help="EXR input: keep the stored data window instead of placing it in the display window")
    parser.add_argument("--quiet", "-q", action="store_true", help="no progress bar")
    from lenslab.cli.display import add_display_arguments
    from lenslab.cli.options import add_jobs_option, add_scheduler_options

    add_display_arguments(parser)
    add_jobs_option(parser, "files to convert")
    add_scheduler_options(parser)


def _glob_root(pattern: str) -> str:
    """The folder a glob pattern starts from: its leading components without wildcards."""
    parts = Path(pattern).parts
    fixed = [p for p in parts[:next((i for i, p in enumerate(parts) if glob.has_magic(p)), len(parts))]]
    return str(Path(*fixed)) if fixed else "."


def expand_inputs(patterns: list[str], recursive: bool = False,
                  roots: dict[str, str] | None = None) -> tuple[list[str], list[tuple[str, str]]]:
    """Files to convert, and (input, reason) for inputs that match nothing.

    Directories give their image files (``recursive``: in every sub-folder too); ``**`` in a glob
    pattern matches any depth. ``roots`` (if given) receives, for every file found in a directory or
    by a pattern, the folder it was found under, so that outputs can mirror the tree.
    """
    from lenslab.io import split_selector

    files: list[str] = []
    missing: list[tuple[str, str]] = []
    roots = {} if roots is None else roots
    for pat in patterns:
        if os.path.isdir(pat):
            walk = Path(pat).rglob("*") if recursive else Path(pat).iterdir()
            found = sorted(str(p) for p in walk if p.is_file() and p.suffix.lower() in INPUT_EXTENSIONS)
            if not found:
                missing.append((pat, "the directory holds no image files"))
            files.extend(found)
            roots.update((f, pat) for f in found)
        elif glob.has_magic(pat) and not os.path.exists(pat):
            found = sorted(p for p in glob.glob(pat, recursive=True) if os.path.isfile(p))
            roots.update((f, _glob_root(pat)) for f in found)
            if not found:
                missing.append((pat, "the pattern matches no file"))
            files.extend(found)
        elif not split_selector(pat)[0].exists():  # (file.exr:part names a part of file.exr)
            missing.append((pat, "no such file or directory"))
        else:
            files.append(pat)
    seen: set[str] = set()
    unique = [f for f in files if not (f in seen or seen.add(f))]
    return unique, missing


def plan_outputs(files: list[str], to: str, output: str | None,
                 roots: dict[str, str] | None = None) -> list[tuple[str, Path]]:
    """(input, output path) pairs; raises OSError/ValueError when -o cannot be used as asked.

    With ``roots`` (from :func:`expand_inputs`), a file found under a folder goes to the same
    sub-folder of ``-o``: the input tree is mirrored."""
    from lenslab.cli.policy import check_output_dir
    from lenslab.errors import FormatError
    from lenslab.io import split_selector

    from lenslab.io.registry import get

    ext = get(to).extensions[0]
    if output is not None:
        out = Path(output)
        as_file = len(files) == 1 and not out.is_dir() and out.suffix != ""
        if not as_file:
            check_output_dir(out, len(files))  # created by run() once everything is checked
    pairs, targets = [], {}
    for f in files:
        src, selector = split_selector(f)
        stem = src.stem + (f"_{selector.replace(':', '_')}" if selector else "")
        if output is None:
            dst = src.with_name(stem + ext)
        elif as_file:
            dst = out
        else:
            sub = Path(os.path.relpath(src.parent, roots[f])) if roots and f in roots else Path(".")
            dst = out / sub / (stem + ext)
        if dst in targets:
            raise FormatError(f"{f} and {targets[dst]} would both be written to {dst}; convert them separately")
        targets[dst] = f
        pairs.append((f, dst))
    return pairs


def convert_many(pairs: list[tuple[str, Path]], options: dict, jobs: int = 0, progress: bool = True
                 ) -> list[tuple[str, str, str | None, list[str]]]:
    """Convert every (input, output) pair, ``jobs`` files at once (0: one per core) on threads of this
    process (:mod:`lenslab.cluster.threads`); returns (input, output, error or None, warnings) in input order."""
    from tqdm import tqdm

    from lenslab.cluster.tasks import guarded
    from lenslab.cluster.threads import default_jobs, run_threads

    from lenslab.cli.convert_file import convert_one

    bar = tqdm(total=len(pairs), unit="img", disable=not progress, file=sys.stderr, leave=False)
    try:
        return run_threads(lambda pair: guarded(pair[0], str(pair[1]), lambda: convert_one(pair[0], str(pair[1]),
                                                                                             options)),
                           pairs, jobs or default_jobs(len(pairs)), lambda _: bar.update(), first_alone=True,
                           fit_memory=not jobs)
    finally:
        bar.close()


def run(args: argparse.Namespace) -> int:
    from lenslab.cli.display import display_options
    from lenslab.cli.options import check_skip_or_overwrite

    check_skip_or_overwrite(args)

    roots: dict[str, str] = {}
    files, missing = expand_inputs(args.inputs, args.recursive, roots)
    from lenslab.cli.options import parse_exposure

    exposure = parse_exposure(args.exposure)
    display = display_options(args)  # bad display names: one usage error before any folder is made
    check_convert_options(args, files, display["display"])
    if args.bits and args.to in ("jpg", "exr", "pfm", "hdr"):
        from lenslab.errors import FormatError
        raise FormatError(f"--bits applies to png, ppm, pgm and tiff, not {args.to}")
    for pat, reason in missing:
        print(f"lenslab convert: {pat}: {reason}", file=sys.stderr)
    if not files:
        print("lenslab convert: error: nothing to convert", file=sys.stderr)
        return 1
    if args.to in VIDEO:  # every input, in order, as one clip
        from lenslab.cli.convert_video import files_to_video
        from lenslab.cli.policy import UsageError

        if not args.output or Path(args.output).suffix.lower() != "." + args.to:
            raise UsageError(f"--to {args.to}: name the clip with -o NAME.{args.to}")
        options = {"tone": args.tone, "exposure": exposure, "overwrite": args.overwrite, "rate": args.rate,
                   "transfer": args.transfer, "codec": args.codec, "quiet": args.quiet}
        files_to_video(files, args.output, options)
        if not args.quiet:
            print(f"wrote {len(files)} frame(s) to {args.output}", file=sys.stderr)
        return 1 if missing else 0
    if args.to in LDR:
        from lenslab.tone import get_curve

        get_curve(args.tone)  # an unknown curve: one usage error, before any folder is made
    if args.to == "exr":
        from lenslab.cli.policy import UsageError
        from lenslab.io.exr import COMPRESSIONS

        if str(args.compression).lower().replace("_compression", "") not in COMPRESSIONS:
            raise UsageError(f"--compression {args.compression}: choose one of {', '.join(COMPRESSIONS)} "
                             "(zip is the most widely readable)")
    pairs = plan_outputs(files, args.to, args.output, roots)
    from lenslab.cluster.command import batch_on_cluster, connect

    client = connect(args)  # an unreachable scheduler: one error, before any folder is made
    if args.output is not None and (len(pairs) > 1 or Path(args.output).suffix == ""):
        from lenslab.cli.policy import make_output_dir

        make_output_dir(args.output)
        for folder in sorted({Path(dst).parent for _, dst in pairs}):
            folder.mkdir(parents=True, exist_ok=True)  # the mirrored sub-folders
    options = {"to": args.to, "tone": args.tone, "exposure": exposure, "overwrite": args.overwrite,
               "quality": args.quality, "bits": args.bits, "pixel_type": args.pixel_type,
               "compression": args.compression, "data_window": args.data_window, "frames": args.frames,
               **display}
    from lenslab.cluster.run import skip_existing

    pairs, skipped = skip_existing(pairs, args.skip_existing)
    if skipped and not args.quiet:
        print(f"lenslab convert: {skipped} output(s) already there, left alone (--skip-existing)", file=sys.stderr)
    if client is not None:
        status = batch_on_cluster("lenslab convert", client, "convert_task", pairs, options, args.quiet, "converted")
        return 1 if status or missing else 0
    progress = not args.quiet and sys.stderr.isatty()
    results = convert_many(pairs, options, jobs=args.jobs, progress=progress)
    for src, _, _, notes in results:
        for note in notes:  # repaired values, clamped halves: reported, never hidden
            print(f"lenslab convert: note: {src}: {note}", file=sys.stderr)
    failed = [(s, e) for s, _, e, _ in results if e]
    for src, err in failed:
        print(f"lenslab convert: FAILED: {err if src in err else f'{src}: {err}'}", file=sys.stderr)
    done = len(results) - len(failed)
    if not args.quiet:
        print(f"converted {done} of {len(results) + skipped} file(s) to {args.to.upper()}"
              + (f"; {len(failed)} failed" if failed else "")
              + (f"; {skipped} already there, left alone" if skipped else ""), file=sys.stderr)
    return 1 if failed or missing else 0
