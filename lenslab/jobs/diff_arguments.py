"""idiff's thresholds as command options, shared by ``lenslab diff`` and ``lenslab validate --reference``."""

from __future__ import annotations

import argparse
import math

from lenslab.jobs.arguments import finite_float, non_negative_int


def non_negative(text: str) -> float:
    """argparse ``type=``: a finite number of at least 0 (an error threshold)."""
    x = finite_float(text)
    if x < 0:
        raise argparse.ArgumentTypeError(f"{str(text)[:40]!r}: must be at least 0")
    return x


def percent(text: str) -> float:
    """argparse ``type=``: a share in percent, 0 to 100."""
    x = non_negative(text)
    if x > 100:
        raise argparse.ArgumentTypeError(f"{str(text)[:40]!r}: must be a percentage from 0 to 100")
    return x


count = non_negative_int  # --allow-failures


def add_threshold_arguments(parser: argparse.ArgumentParser) -> None:
    """idiff's thresholds, for ``lenslab diff`` and ``lenslab validate --reference``."""
    g = parser.add_argument_group("thresholds (idiff's options and defaults)")
    g.add_argument("--fail", type=non_negative, default=1e-6, metavar="E",
                   help="a pixel fails when a channel differs by more than E (default 1e-6)")
    g.add_argument("--fail-relative", type=non_negative, default=0.0, metavar="R",
                   help="... and, when given, by more than R relative to the mean of the two values")
    g.add_argument("--fail-percent", type=percent, default=0.0, metavar="P",
                   help="FAILURE only when more than P %% of the pixels fail (default 0)")
    g.add_argument("--hard-fail", type=non_negative, default=math.inf, metavar="E",
                   help="FAILURE when any one channel differs by more than E, whatever the share")
    g.add_argument("--allow-failures", type=count, default=0, metavar="N",
                   help="PASS when at most N pixels fail, by any amount")
    g.add_argument("--warn", type=non_negative, default=1e-6, metavar="E", help="as --fail, for WARNING")
    g.add_argument("--warn-relative", type=non_negative, default=0.0, metavar="R", help="as --fail-relative")
    g.add_argument("--warn-percent", type=percent, default=0.0, metavar="P", help="as --fail-percent")
    g.add_argument("--hard-warn", type=non_negative, default=math.inf, metavar="E", help="as --hard-fail")


def thresholds_from(args: argparse.Namespace):
    from lenslab.metrics.diff import Thresholds

    return Thresholds(fail=args.fail, warn=args.warn, fail_relative=args.fail_relative,
                      warn_relative=args.warn_relative, fail_percent=args.fail_percent,
                      warn_percent=args.warn_percent, hard_fail=args.hard_fail, hard_warn=args.hard_warn,
                      allow_failures=args.allow_failures)
