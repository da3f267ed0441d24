"""Entry point of the ``lenslab`` command.

Every subcommand is a module ``lenslab.cli.<module>`` with two functions:

- ``add_arguments(parser)``: declares its options (argparse only; no heavy import at module level),
- ``run(args) -> int``: does the work (heavy imports happen here) and returns the exit code.

Keeping the command modules light is what makes ``lenslab --help`` instant.

Commands of other packages join through the ``lenslab.commands`` entry-point group (pyproject.toml):
each entry names a module with the same two functions and a one-line ``HELP``. The tracer's
``validate`` and the gallery's ``demo`` come in this way, so lenslab itself never imports them.
"""

from __future__ import annotations

import argparse
import importlib
import sys

from lenslab.registry import Registry

# name -> (module, one-line help)
COMMANDS: Registry[tuple[str, str]] = Registry.from_mapping("command", {
    "info": ("info", "print format, size, channels, statistics and lens model of image files"),
    "convert": ("convert", "convert images between EXR, HDR, PFM, TIFF, PNG, JPG and PPM/PGM, and video frames (batch, with tone mapping)"),
    "lenses": ("lenses", "list every lens model with its parameters, ranges and defaults"),
    "warp": ("warp", "reproject images from one lens into another (HDR in, HDR out)"),
    "stmap": ("stmap", "write a lens-to-lens warp as an ST map (Nuke's STMap convention) for compositors"),
    "tonemap": ("tonemap", "tone-map an HDR image to a display image with a chosen curve"),
    "curves": ("curves", "plot every tone curve on one chart"),
    "compare-tones": ("compare_tones", "side-by-side strip of one image under several tone curves"),
    "fit": ("fit", "fit lens models and tone curves with nlopt"),
    "camera": ("camera", "show calibrated cameras and convert them between OpenCV, Kalibr, COLMAP and OCamCalib files"),
    "diff": ("diff", "compare two images: mean, RMS, max and relative error, PSNR, FLIP; idiff's thresholds and exit codes"),
    "bench": ("bench", "benchmarks, reported as ratios against a baseline measured in the same run"),
}, summary=lambda entry: entry[1])

ENTRY_POINTS = "lenslab.commands"


def plugin_commands() -> dict:
    """``name -> entry point`` of the ``lenslab.commands`` group (read from the installed metadata)."""
    from importlib.metadata import entry_points

    return {ep.name: ep for ep in entry_points(group=ENTRY_POINTS) if ep.name not in COMMANDS}


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The whole command line, or with ``command`` (a built-in command's name) only that command's parser:
    a command starts without importing the other commands' modules or reading the installed plugins."""
    from lenslab import __version__
    from lenslab.jobs.arguments import ArgumentParser

    parser = ArgumentParser(
        prog="lenslab",
        description=(
            "Lenses and tone curves for HDR images. Reproject panoramas into fisheye, swirl, "
            "distorted and tiled views, tone-map them, convert between image formats, and check "
            "every warp against a direct ray-traced render."
        ),
        epilog="Run 'lenslab COMMAND --help' for the options of one command.",
    )
    parser.add_argument("--version", action="version", version=f"lenslab {__version__}")
    add_debug_option(parser)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name, (module_name, help_text) in COMMANDS.items():
        if command is not None and name != command:
            continue
        try:
            module = importlib.import_module(f"lenslab.cli.{module_name}")
        except ModuleNotFoundError as exc:
            if exc.name != f"lenslab.cli.{module_name}":
                raise
            continue  # command not built yet
        p = sub.add_parser(name, help=help_text, description=(module.__doc__ or help_text).strip(),
                           formatter_class=argparse.RawDescriptionHelpFormatter)
        module.add_arguments(p)
        add_debug_option(p, argparse.SUPPRESS)
        p.set_defaults(_module=module)
    for name, ep in sorted(plugin_commands().items() if command is None else ()):
        module = ep.load()  # a light module: its heavy imports happen in run()
        p = sub.add_parser(name, help=getattr(module, "HELP", None), description=(module.__doc__ or "").strip(),
                           formatter_class=argparse.RawDescriptionHelpFormatter)
        module.add_arguments(p)
        add_debug_option(p, argparse.SUPPRESS)
        p.set_defaults(_module=module)
    return parser


def add_debug_option(parser, default=False) -> None:
    parser.add_argument("--debug", action="store_true", default=default,
                        help="on an error, print the full traceback too (for a bug report)")


def main(argv: list[str] | None = None) -> int:
    import os

    from lenslab.jobs.funnel import EXIT_USAGE, run_command

    # the commands run threads of their own (bands of rows, the codecs'): OpenBLAS's, started with NumPy, would
    # only spin beside them (50 ms of a core at every start)
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

    argv = sys.argv[1:] if argv is None else list(argv)
    first = next((a for a in argv if not a.startswith("-")), None)  # the only options before it take no value
    parser = build_parser(first if first in COMMANDS else None)
    args = parser.parse_args(argv)  # a usage error: one line on stderr and SystemExit(2)
    if getattr(args, "_module", None) is None:
        parser.print_help()
        return EXIT_USAGE
    return run_command(args._prog, lambda: args._module.run(args), debug=getattr(args, "debug", False))


def console() -> None:
    """The ``lenslab`` command (and ``python -m lenslab``): :func:`main`, then the process ends without the
    interpreter's teardown (:mod:`lenslab.cli.process_exit`)."""
    code = main()  # a usage error or --help: SystemExit, the interpreter's usual exit
    from lenslab.cli.process_exit import exit_now

    exit_now(code)


if __name__ == "__main__":  # pragma: no cover
    console()
