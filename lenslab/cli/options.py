"""Option values that several commands parse the same way (standard library only, so --help stays instant)."""

from __future__ import annotations

import argparse


def parse_exposure(text: str) -> float | str:
    """``--exposure``: a number of stops, or ``"auto"``; anything else is a ToneError that says so."""
    if str(text).strip().lower() == "auto":
        return "auto"
    try:
        return float(text)
    except ValueError:
        from lenslab.errors import ToneError

        raise ToneError(f"--exposure must be a number of stops or 'auto', not {text!r}") from None


def add_jobs_option(parser, what: str = "files") -> None:
    """``--jobs N`` of a batch on this machine: how many ``what`` at once on threads of the process."""
    from lenslab.cli.policy import non_negative_int

    parser.add_argument("--jobs", "-j", type=non_negative_int, default=0, metavar="N",
                        help=f"how many {what} at once on this machine (default 0: one per CPU core, as many as the "
                             "memory holds judging by the first file; 1: one after the other, each on every core)")


def check_skip_or_overwrite(args) -> None:
    """``--skip-existing`` and ``--overwrite`` say opposite things of an existing output: a usage error."""
    if getattr(args, "skip_existing", False) and getattr(args, "overwrite", False):
        from lenslab.cli.policy import UsageError

        raise UsageError("--skip-existing leaves existing outputs alone and --overwrite replaces them: give one")


def add_scheduler_options(parser, skip_existing: bool = True) -> None:
    """``--scheduler``, ``--scheduler-file`` (and ``--skip-existing``) of every batch command: one task
    per file on a Dask cluster (:mod:`lenslab.cluster`)."""
    group = parser.add_argument_group("running on a Dask cluster (see README: 'Beyond one machine')")
    group.add_argument("--scheduler", metavar="ADDRESS", default=None,
                       help="run the work on the Dask cluster whose scheduler is at ADDRESS (e.g. "
                            "tcp://host:8786), one task per file (per tile for a render); default: "
                            "$DASK_SCHEDULER_ADDRESS, else this machine. The workers must see the same files")
    group.add_argument("--scheduler-file", metavar="FILE", default=None,
                       help="the same, with the address read from the file 'dask scheduler --scheduler-file' wrote")
    if skip_existing:
        group.add_argument("--skip-existing", action="store_true",
                           help="leave outputs that already exist alone and do the others (resumes an "
                                "interrupted batch)")


class Once(argparse.Action):
    """An option that may be given once: a second ``--from`` would silently replace the first, so it is a
    usage error (argparse's: one line, exit 2)."""

    def __call__(self, parser, namespace, values, option_string=None):
        seen = namespace.__dict__.setdefault("_given_once", set())
        if self.dest in seen:
            parser.error(f"{option_string} given twice; give it once")
        seen.add(self.dest)
        setattr(namespace, self.dest, values)


def check_tone_applies(flag: str, given: bool, display: str | None, outputs) -> None:
    """A tone curve named on the command line (``given``) must have something to do: refused with
    ``--display`` (an OpenColorIO view maps scene light itself) and for outputs that keep linear light.
    ``outputs``: ``(name, why)`` for each output that keeps linear light (why it does)."""
    if not given:
        return
    from lenslab.cli.policy import UsageError

    if display:
        raise UsageError(f"{flag} and --display both map scene light to the display: give one (--display "
                         "with --view 'ACES 2.0 - SDR' tone-maps as it transforms)")
    for name, why in outputs:
        raise UsageError(f"{flag} applies to display formats (PNG, JPG, PPM); {name}: {why}")


def check_frames_apply(frames, stills) -> None:
    """``--frames`` picks frames of videos: a usage error when an input (of ``stills``) is a still image."""
    for still in stills:
        from lenslab.cli.policy import UsageError

        raise UsageError(f"--frames picks frames of a video; {still} is a still image")
