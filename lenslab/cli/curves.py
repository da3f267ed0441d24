"""Plot every tone curve on one chart, so the choice can be seen.

The horizontal axis is the scene-linear input on a log axis, labelled in stops from 1.0 (0 = an input
of 1; middle grey 0.18 is -2.5); the left panel shows the sRGB-encoded display value a viewer sees,
the right one the display-linear output. reinhard2002 is drawn for an image whose log-average is
middle grey. drago and mantiuk are not per-pixel curves: they are drawn dashed as their response
to a horizontal ramp image covering the same range, which depends on the image.

  lenslab curves -o curves.png
  lenslab curves --list
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
    """(input values, display-linear output) for plotting one curve."""
    import numpy as np

    from lenslab import tone

    x = np.exp2(np.linspace(stops[0], stops[1], n)).astype(np.float32)
    curve = tone.get_curve(name)
    if curve.kind == "local":
        ramp = np.repeat(np.repeat(x[None, :, None], 8, axis=0), 3, axis=2)
        y = tone.tonemap(ramp, name, exposure=exposure)[4, :, 1]
    elif curve.kind == "image":
        y = tone.reinhard2002(x * np.float32(2.0 ** exposure), log_avg=tone.MIDDLE_GREY)
    else:
        y = tone.tonemap(x, name, exposure=exposure)
    return x, y


def run(args: argparse.Namespace) -> int:
    from lenslab import tone

    if args.list:
        print(tone.describe_curves())
        return 0
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    from lenslab.io.atomic import atomic_write_path
    from lenslab.io.encode import encode_srgb

    names = [tone.get_curve(n).name for n in args.curves.split(",") if n.strip()] or list(tone.CURVES)
    if not args.stops[0] < args.stops[1]:
        from lenslab.errors import ToneError
        raise ToneError("--stops LOW HIGH needs LOW < HIGH")
    fig, (ax_enc, ax_lin) = plt.subplots(1, 2, figsize=(14, 6), constrained_layout=True)
    cmap = plt.get_cmap("tab20")
    for i, name in enumerate(names):
        x, y = curve_samples(name, args.stops, args.exposure)
        style = "--" if tone.CURVES[name].kind == "local" else "-"
        for ax, values in ((ax_enc, encode_srgb(y)), (ax_lin, y)):
            ax.plot(x, values, style, color=cmap(i % 20), label=name, linewidth=1.6)
    for ax, title in ((ax_enc, "display value (sRGB-encoded)"), (ax_lin, "display-linear output")):
        ax.set_xscale("log", base=2)
        ax.xaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{np.log2(v):+.0f}"))
        ax.set_xlabel("scene-linear input, stops from 1.0")
        ax.set_title(title)
        ax.set_ylim(-0.02, 1.02)
        ax.axvline(tone.MIDDLE_GREY, color="0.6", linewidth=0.8, linestyle=":")
        ax.grid(True, which="major", alpha=0.3)
    ax_enc.legend(loc="upper left", fontsize=9)
    fig.suptitle(f"lenslab tone curves (exposure {args.exposure:+g} stops; dotted line: middle grey 0.18)")
    with atomic_write_path(args.output) as tmp:
        fig.savefig(tmp, dpi=110, format=str(args.output).rsplit(".", 1)[-1].lower())
    plt.close(fig)
    print(f"{args.output}: {len(names)} curves", file=sys.stderr)
    return 0
