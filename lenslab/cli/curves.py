"""Plot every tone curve on one chart, so the choice can be seen.

The horizontal axis is the scene-linear input on a log axis, labelled in stops from 1.0 (0 = an input
of 1; middle grey 0.18 is -2.5); the left panel shows the sRGB-encoded display value a viewer sees,
the right one the display-linear output. reinhard2002 is drawn for an image whose log-average is
middle grey. drago and mantiuk are not per-pixel curves: they are drawn dashed as their response
to a horizontal ramp image covering the same range, which depends on the image.

  lenslab curves -o curves.png
  lenslab curves --list

From Python, ``lenslab.tone.plot.plot_curves(names, stops, exposure)`` returns the same chart as a
matplotlib Figure.
"""

from __future__ import annotations

import argparse
import math
import sys

CHART_FORMATS = ("png", "svg", "pdf")
STOPS = (-126, 127)  # the normal range of float32 in stops: beyond it the samples underflow to 0 or overflow to inf


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("-o", "--output", default="curves.png", help="chart to write (PNG, SVG or PDF; default curves.png)")
    from lenslab.jobs.arguments import add_tones_option

    add_tones_option(parser, help="comma-separated subset of curves (default: every curve)")
    from lenslab.jobs.arguments import finite_float

    parser.add_argument("--stops", type=finite_float, nargs=2, default=(-10.0, 8.0), metavar=("LOW", "HIGH"),
                        help=f"input range in stops from 1.0 (default -10 8; with --exposure within {STOPS[0]} "
                             f"and {STOPS[1]}, the range of 32-bit floats)")
    parser.add_argument("--exposure", type=finite_float, default=0.0, help="exposure in stops applied before the curves")
    parser.add_argument("--list", action="store_true", help="print every curve with its parameters and exit")
    parser.add_argument("--overwrite", action="store_true", help="replace an existing chart")


def curve_samples(name: str, stops, exposure: float = 0.0, n: int = 512):
    """(input values, display-linear output) for plotting one curve (see :mod:`lenslab.tone.plot`)."""
    from lenslab.tone.plot import curve_samples as samples

    return samples(name, stops, exposure, n)


def run(args: argparse.Namespace) -> int:
    from lenslab import tone

    if args.list:
        print(tone.describe_curves())
        return 0
    from lenslab.errors import UsageError
    from lenslab.jobs.policy import check_output
    from lenslab.atomic import atomic_write_path

    kind = str(args.output).rsplit(".", 1)[-1].lower()
    if kind not in CHART_FORMATS:
        raise UsageError(f"{args.output}: a chart is written as {', '.join(CHART_FORMATS)}; give one of those extensions")
    low, high = args.stops
    if not (math.isfinite(low) and math.isfinite(high) and low < high):
        raise UsageError(f"--stops {low:g} {high:g}: give a finite range with LOW below HIGH, e.g. -10 8")
    if not (STOPS[0] <= low + args.exposure and high + args.exposure <= STOPS[1]):
        shift = f" with --exposure {args.exposure:g}" if args.exposure else ""
        raise UsageError(f"--stops {low:g} {high:g}{shift}: keep the range within {STOPS[0]} and {STOPS[1]} stops, "
                         "the range of 32-bit floats")
    if not math.isfinite(args.exposure):
        raise UsageError(f"--exposure {args.exposure}: give a finite number of stops")
    names = [n.strip() for n in (args.curves or "").split(",") if n.strip()]
    if args.curves is not None and not names:
        raise UsageError(f"--curves is empty; give names from: {', '.join(tone.CURVES)} (or leave it out for all)")
    for name in names:
        tone.get_curve(name)  # an unknown name is a usage error, before anything is drawn
    check_output(args.output, (), args.overwrite)
    from lenslab.tone.plot import plot_curves

    fig = plot_curves(args.curves or "", args.stops, args.exposure)
    with atomic_write_path(args.output, overwrite=args.overwrite) as tmp:
        fig.savefig(tmp, dpi=110, format=kind)
    count = len(names) or len(tone.CURVES)
    print(f"{args.output}: {count} curves", file=sys.stderr)
    return 0
