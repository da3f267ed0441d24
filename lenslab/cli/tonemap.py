"""Tone-map an HDR image (EXR, PFM, ...) to a display image with a chosen curve.

Exposure comes first (stops, or 'auto': the log-average luminance, leaving out the darkest and
brightest percent, goes to middle grey), then the curve, per channel or on luminance (keeps hue).
NaN, +inf and negative input values are repaired (to 0, white, 0) and counted on stderr; the colours of
a Display P3 or Adobe RGB file outside sRGB are clipped per channel, with a note counting the pixels.
LDR outputs (JPG, PNG, PPM/PGM) are sRGB-encoded and quantised with rounding (dithered unless
--no-dither); float outputs (EXR, PFM, and TIFF without --bits) keep the display-linear values; a TIFF
with --bits 8 or 16 holds sRGB-encoded integers of that depth. A photo's camera EXIF (maker,
model, lens, focal length, exposure, date; never GPS) goes with it into JPG, PNG, TIFF and EXR outputs.

Examples:
  lenslab tonemap pano.exr -o pano.jpg
  lenslab tonemap pano.exr -o pano.png --tone aces --exposure auto --luminance
  lenslab tonemap pano.exr -o pano.jpg --tone hable --param preset=gdc --param white=8
  lenslab tonemap 'renders/*.exr' -o previews/ --format jpg --exposure auto
  lenslab tonemap shots/ -o previews/ --scheduler tcp://host:8786   (one task per file on a Dask cluster)
  lenslab curves --list        (every curve with its parameters)
"""

from __future__ import annotations

import argparse
import contextlib
import sys
import warnings
from pathlib import Path


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("inputs", nargs="+", metavar="INPUT",
                        help="HDR images to read: files (EXR selectors like file.exr:left work), folders or glob "
                             "patterns ('renders/*.exr', quoted)")
    parser.add_argument("-o", "--output", required=True,
                        help="image to write (format from the extension) for one input; for several, a folder "
                             "(created if missing) that gets one image per input in --format")
    from lenslab.cli.convert import FORMATS
    from lenslab.jobs.arguments import OneFormat

    parser.add_argument("--format", "--to", dest="format", choices=FORMATS, default=None, metavar="FORMAT",
                        action=OneFormat,
                        help=f"format of the images written into an -o folder: {', '.join(FORMATS)} (default png; "
                             "--to, as convert names it, is the same option); for one output file its extension "
                             "says it, and a --format that differs is refused")
    from lenslab.jobs.arguments import add_tone_option, non_empty

    add_tone_option(parser, "curve", default=None, type=non_empty,
                    help="tone curve (default hable, the Uncharted 2 filmic curve); 'lenslab curves --list' shows all")
    parser.add_argument("--exposure", default="0",
                        help="exposure in stops applied before the curve, or 'auto' (default 0)")
    from lenslab.jobs.arguments import add_tone_mode_option

    add_tone_mode_option(parser, "apply the curve to R, G and B separately (default; bright colours go to white)",
                         "apply the curve to luminance and scale RGB by it (keeps hue and saturation)")
    parser.add_argument("--param", action="append", default=[], metavar="K=V",
                        help="a curve parameter, e.g. --param white=8 (repeatable)")
    parser.add_argument("--primaries", default=None,
                        help="primaries the image's values are on, for the luminance weights of --luminance, "
                             "--exposure auto and the curves that read luminance (a colour-science name such as "
                             "'ITU-R BT.2020', default sRGB). For files without a colour tag (PFM, an untagged "
                             "EXR): a file with an ICC profile, cICP chunk or EXR chromaticities is converted "
                             "to sRGB's primaries when read, and sRGB's weights apply to it")
    parser.add_argument("--dither", action=argparse.BooleanOptionalAction, default=True,
                        help="dither when quantising to 8/16-bit to avoid banding in smooth skies (default on)")
    parser.add_argument("--bits", type=int, choices=(8, 16), default=None,
                        help="bit depth for PNG/PPM/PGM output (default 8), and for TIFF: sRGB-encoded "
                             "integers instead of floats")
    parser.add_argument("--overwrite", action="store_true",
                        help="replace an existing output file (never the input)")
    parser.add_argument("-q", "--quiet", action="store_true", help="print nothing but errors and repairs")
    from lenslab.cli.display import add_display_arguments
    from lenslab.jobs.arguments import add_jobs_option, add_scheduler_options

    add_display_arguments(parser)
    add_jobs_option(parser, "files to tone-map (with several inputs)")
    add_scheduler_options(parser)


def parse_params(items: list[str]) -> dict:
    """["white=8", "preset=gdc"] -> {"white": "8", "preset": "gdc"} (the curve validates the values)."""
    from lenslab.errors import ToneError

    params = {}
    for item in items:
        key, sep, value = item.partition("=")
        if not sep or not key.strip():
            raise ToneError(f"--param {item!r} is not of the form NAME=VALUE (e.g. --param white=8)")
        params[key.strip()] = value.strip()
    return params


@contextlib.contextmanager
def repairs_reported(prog: str, label: str, report: bool = True):
    """Tone mapping's repairs of bad values (:class:`lenslab.tone.ToneWarning`) inside the block, printed as one
    stderr line each (dropped when not ``report``: a repair already told); other warnings pass on."""
    from lenslab import tone

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", tone.ToneWarning)
        yield
    for w in caught:
        if isinstance(w.message, tone.ToneWarning):
            if report:
                print(f"{prog}: note: {label}: {w.message}", file=sys.stderr)
        else:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)


def run(args: argparse.Namespace) -> int:
    from lenslab import io, tone
    from lenslab.errors import UsageError
    from lenslab.io.registry import get as get_format
    from lenslab.jobs.arguments import check_skip_or_overwrite, parse_exposure
    from lenslab.jobs.policy import check_output, output_format, refuse_inputs

    check_skip_or_overwrite(args)
    from lenslab.cli.tonemap_batch import is_batch, run_many

    if not is_batch(args):  # the input named as the output: a usage error before any file is read
        refuse_inputs([args.output], [io.split_selector(args.inputs[0])[0]])
    curve_given, args.curve = args.curve is not None, args.curve or "hable"

    curve = tone.get_curve(args.curve)
    params = parse_params(args.param)
    curve.resolve(params)  # fail before reading a large file
    from lenslab.cli.display import display_options
    display = display_options(args)  # bad display names: one usage error before any file is read
    from lenslab.jobs.arguments import check_tone_applies, typed

    check_tone_applies(typed(args, "curve", "--tone"), curve_given, display["display"], [])
    from lenslab.jobs.primaries import applied_primaries, check_primaries

    check_primaries(args.primaries, args.mode, args.exposure, [curve], display["display"])
    # a format that cannot hold the display's codes, or the channels an input's header declares: refused
    # before any file is read
    target = get_format(args.format or ("png" if is_batch(args) else output_format(args.output)))
    if display["display"]:
        from lenslab.jobs.display import check_display_outputs

        check_display_outputs(display["display"], [target], args.bits)
    if is_batch(args):  # (each input's channels checked once the outputs are planned)
        return run_many(args, curve.name, params, None if display["display"] else target)
    if not display["display"]:
        from lenslab.jobs.stages import check_channels_fit

        check_channels_fit(args.inputs[0], target)
    args.input = args.inputs[0]
    from lenslab.jobs.plan import sweep_outputs

    sweep_outputs([(args.input, args.output)])  # temporaries of killed runs
    if getattr(args, "skip_existing", False) and Path(args.output).is_file():
        if not args.quiet:
            print(f"lenslab tonemap: {args.output} already there, left alone (--skip-existing)", file=sys.stderr)
        return 0
    exposure = parse_exposure(args.exposure)  # a bad value: one usage error before the image is read
    check_output(args.output, [args.input], args.overwrite)
    named = output_format(args.output)  # an unknown extension: one usage error before the image is read
    if args.format and get_format(args.format).name != named:
        typed = getattr(args, "_curves_given", {}).get("format", ("--format",))[0]  # --format or --to
        raise UsageError(f"-o {args.output}: the name says {named} but the output format asked is {args.format}; "
                         f"give a name with the format's extension, or leave {typed} out")
    from lenslab.jobs.funnel import working_on
    from lenslab.jobs.progress import RowBar

    # each step that outlasts the patience is named on a terminal: reading, then tone-mapping and writing
    steps = RowBar(Path(args.input).name) if not args.quiet and sys.stderr.isatty() else None
    try:
        with working_on(args.input):
            image, meta = io.read(args.input)
        return _develop(args, image, meta, curve, params, exposure, display, steps)
    finally:
        if steps is not None:
            steps.close()


def _develop(args, image, meta, curve, params, exposure, display, steps) -> int:
    """The single image's tone mapping and writing, ``steps`` (a :class:`~lenslab.jobs.progress.RowBar` or None)
    told each step."""
    from lenslab.jobs.primaries import applied_primaries

    if steps is not None:  # (the exposure measured, the curve applied, the file encoded: one step to the user)
        steps.status(f"tone-mapping and writing {Path(args.output).name}")
    from lenslab.jobs.tonemap import TonemapJob

    with repairs_reported("lenslab tonemap", args.input):  # a file read onto Rec.709: sRGB's weights, said
        args.primaries = applied_primaries(args.primaries, meta)
    if not display["display"]:
        from lenslab.jobs.stages import resolved_exposure

        from lenslab.io import carries_alpha

        # a curve the exposure cannot change (mantiuk) says so in its note; no stops are printed for it
        exposure = resolved_exposure(image, exposure, args.primaries, args.input,
                                     args.quiet or bool(curve.ignores_exposure),
                                     carries_alpha(meta, image.shape[2]) if image.ndim == 3 else False)
    job = TonemapJob.from_options(args, curve=curve.name, params=params, exposure=exposure, **display)
    from lenslab.current_input import from_input

    with repairs_reported("lenslab tonemap", args.input), from_input(args.input):
        job.write(args.output, image, meta, source=args.input)  # the batch's stages: the look, then the encode stage
    if not args.quiet:
        h, w_ = image.shape[:2]
        if display["display"]:
            from lenslab.cli.display import say_view

            say_view(args.output, display)
        else:
            how = "a local operator on luminance" if curve.kind == "local" else args.mode  # mode does not apply
            stops = "the exposure has no effect" if curve.ignores_exposure else f"exposure {float(exposure):+.2f} stops"
            print(f"{args.output}: {w_} x {h}, curve {curve.name} ({how}), {stops}", file=sys.stderr)
    return 0
