"""``--display``/``--view``/``--colorspace``/``--ocio``: an OpenColorIO display transform instead of a tone
curve, shared by the commands that write display images (see :mod:`lenslab.io.ocio`)."""

from __future__ import annotations

import argparse


def add_display_arguments(parser: argparse.ArgumentParser, title: str | None = None, instead_of: str = "--tone",
                          hdr: bool = True) -> None:
    """The group of display options; ``instead_of`` names the command's tone-curve option, ``hdr`` says
    whether the command writes HDR displays (16-bit PNG/TIFF)."""
    g = parser.add_argument_group(title or f"OpenColorIO display transform (instead of {instead_of})")
    g.add_argument("--display", metavar="NAME",
                   help="display of the OpenColorIO config, e.g. sRGB, 'Display P3'"
                        + (", Rec.2100-PQ (HDR: written as 16-bit PNG/TIFF)" if hdr else " (SDR displays)")
                        + "; any unique part of the name works")
    g.add_argument("--view", metavar="NAME",
                   help="view of that display (default: the display's first), e.g. 'ACES 2.0 - SDR', "
                        "Un-tone-mapped")
    g.add_argument("--colorspace", metavar="NAME",
                   help="the input's colour space in the config (default: linear Rec.709, which lenslab reads "
                        "every file into; EXR chromaticities are converted on reading)")
    g.add_argument("--ocio", metavar="CONFIG",
                   help="OpenColorIO config file or ocio:// name (default ocio://default; "
                        "ocio://studio-config-latest adds Rec.2100-HLG)")


def display_options(args: argparse.Namespace) -> dict:
    """The display keys of a command's option dict; checks the names before any work starts."""
    opts = {k: getattr(args, k, None) for k in ("display", "view", "colorspace", "ocio")}
    if opts["display"] is None:
        for k in ("view", "colorspace", "ocio"):
            if opts[k] is not None:
                from lenslab.errors import UsageError

                raise UsageError(f"--{k} goes with --display NAME")
        return opts
    from lenslab.errors import UsageError
    from lenslab.io.ocio import OCIOError, processor

    if str(getattr(args, "exposure", None)).strip().lower() == "auto":  # a usage error, before any file is read
        raise UsageError("--exposure auto goes with a tone curve; give a number of stops with --display")

    try:  # unknown names: one usage error now, before any file is read
        processor(opts["display"], opts["view"], opts["colorspace"], opts["ocio"])
    except OCIOError as exc:
        raise UsageError(str(exc)) from None
    return opts


def say_view(where: str, opts: dict, quiet: bool = False) -> None:
    """The display and view a command used, said once on standard error as ``WHERE: display D, view V`` (the
    names the config matched; the view it defaults to when none was given); nothing without ``--display``."""
    if not opts.get("display") or quiet:
        return
    import sys

    from lenslab.io.ocio import processor

    _, (d, v, _) = processor(opts["display"], opts["view"], opts["colorspace"], opts["ocio"])
    print(f"{where}: display {d}, view {v}", file=sys.stderr)
