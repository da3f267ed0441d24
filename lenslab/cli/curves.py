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
import sys


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("-o", "--output", default="curves.png", help="chart to write (PNG, SVG or PDF; default curves.png)")
    parser.add_argument("--curves", default="", help="comma-separated subset of curves (default: every curve)")
    parser.add_argument("--stops", type=float, nargs=2, default=(-10.0, 8.0), metavar=("LOW", "HIGH"),
                        help="input range in stops from 1.0 (default -10 8)")
    parser.add_argument("--exposure", type=float, default=0.0, help="exposure in stops applied before the curves")
    parser.add_argument("--list", action="store_true", help="print every curve with its parameters and exit")


def curve_samples(name: str, stops, exposure: float = 0.0, n: int = 512):
    """(input values, display-linear output) for plotting one curve (see :mod:`lenslab.tone.plot`)."""
    from lenslab.tone.plot import curve_samples as samples

    return samples(name, stops, exposure, n)


def run(args: argparse.Namespace) -> int:
    from lenslab import tone

    if args.list:
        print(tone.describe_curves())
        return 0
    from lenslab.io.atomic import atomic_write_path
    from lenslab.tone.plot import plot_curves

    fig = plot_curves(args.curves, args.stops, args.exposure)
    with atomic_write_path(args.output) as tmp:
        fig.savefig(tmp, dpi=110, format=str(args.output).rsplit(".", 1)[-1].lower())
    count = len([n for n in args.curves.split(",") if n.strip()]) or len(tone.CURVES)
    print(f"{args.output}: {count} curves", file=sys.stderr)
    return 0
