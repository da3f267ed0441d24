"""Command-line argument types and option groups every command shares (``lenslab``, ``tracer``,
``python -m gallery``): one-line argparse errors, checked numbers, sizes, ``--jobs`` and the cluster options.

A bad value is refused here, once, before any work (exit code 2), so that a batch never reports the
same usage mistake for each of its files. Standard library only, so ``--help`` stays instant.
"""

from __future__ import annotations

import argparse
import math
import re
import sys

from lenslab.errors import UsageError

EXIT_USAGE = 2


class ArgumentParser(argparse.ArgumentParser):
    """argparse with one-line errors: ``PROG: error: MESSAGE (see PROG --help)``, exit code 2.

    A bad value is reported by its option's ``type=`` function (an ``argparse.ArgumentTypeError``
    whose message says what is expected); argparse's usage dump is left for ``--help``.
    """

    def __init__(self, *args, **kwargs):
        # No prefix matching: '--to' is never read as '--tone', nor '--only' as '--only-threads'. The commands'
        # subparsers are made of this class too, so none of them matches prefixes either.
        kwargs.setdefault("allow_abbrev", False)
        super().__init__(*args, **kwargs)
        # No option starts with a digit: "-100x100" or "-3e-5" after an option is its (bad or negative)
        # value, for the option's type to judge, not an unknown option.
        self._negative_number_matcher = re.compile(r"^-\.?\d")

    def error(self, message: str, prog: str | None = None):  # noqa: D401 - argparse's hook
        prog = prog or self.prog
        unknown = self.unknown_options() if message.startswith("the following arguments are required") else []
        if unknown:  # a misspelt option first: the arguments said missing may be what it was meant to give
            hint = self.options_meant(unknown)
            message = f"unrecognized arguments: {' '.join(unknown)}" + (f"; {hint}" if hint else "")
        print(f"{prog}: error: {message} (see '{prog} --help')", file=sys.stderr)
        raise SystemExit(EXIT_USAGE)

    def parse_known_args(self, args=None, namespace=None):
        self._words = list(sys.argv[1:] if args is None else args)  # for error(): the options it does not know
        namespace, extras = super().parse_known_args(args, namespace)
        if not getattr(namespace, "_prog", None):  # the innermost command given ('lenslab fit lens'): errors name it
            namespace._prog = self.prog
        if extras and not getattr(namespace, "_extras_prog", None):  # the innermost command that was left them
            namespace._extras_prog = self.prog
            namespace._extras_hint = self.options_meant(extras)
        return namespace, extras

    def unknown_options(self) -> list[str]:
        """The words being parsed that are options this parser does not have (none for a parser of subcommands,
        whose words after the command are its subcommand's)."""
        if self._subparsers is not None:
            return []
        words = getattr(self, "_words", [])
        words = words[:words.index("--")] if "--" in words else words
        known = self._option_string_actions
        return [w for w in words if w[:1] in self.prefix_chars and len(w) > 1 and " " not in w
                and not self._negative_number_matcher.match(w) and w.partition("=")[0] not in known
                and not (w[1] not in self.prefix_chars and w[:2] in known)]  # (-ofile: -o with its value)

    def options_meant(self, words: list[str]) -> str:
        """For unknown options that begin an option of this parser ('--to' of '--tone'), the options meant."""
        hints = []
        for word in words:
            word = word.partition("=")[0]
            whole = sorted(o for o in self._option_string_actions if o.startswith(word) and o != word)
            if word.startswith("--") and whole:
                hints.append(f"{word} is not an option (options are never abbreviated): did you mean "
                             f"{' or '.join(whole)}?")
            elif word.startswith("--"):  # a misspelling (--src-size, --szie): the closest option, if one is close
                from difflib import get_close_matches

                close = get_close_matches(word, [o for o in self._option_string_actions if o.startswith("--")], 1, 0.75)
                if close:
                    hints.append(f"{word} is not an option: did you mean {close[0]}?")
        return "; ".join(hints)

    def parse_args(self, args=None, namespace=None):
        """As argparse's, with an unknown option blamed on the command it was given to ('lenslab tonemap: error:
        unrecognized arguments: --bogus', pointing at 'lenslab tonemap --help'), not on the whole program."""
        namespace, extras = self.parse_known_args(args, namespace)
        if extras:
            hint = getattr(namespace, "_extras_hint", "")
            self.error(f"unrecognized arguments: {' '.join(extras)}" + (f"; {hint}" if hint else ""),
                       getattr(namespace, "_extras_prog", None))
        return namespace


#: the spellings of the option that names one tone curve (``--tone hable``): the first is the one ``--help`` and the
#: messages use; the others are accepted on every such command, so a script written for one command works for all
TONE_OPTION = ("--tone", "--curve")
#: the spellings of an option that names several curves (``--curves hable,aces``): one curve is a list of one
TONES_OPTION = ("--curves", "--tone", "--curve")


def add_tone_option(parser, dest: str, **kwargs):
    """Declare a command's tone-curve option under every spelling of :data:`TONE_OPTION`, into ``args.<dest>``."""
    kwargs.setdefault("metavar", "CURVE")
    return parser.add_argument(*TONE_OPTION, dest=dest, action=OneCurve, **kwargs)


def add_tones_option(parser, dest: str = "curves", **kwargs):
    """Declare a command's option of comma-separated curve names under every spelling of :data:`TONES_OPTION`."""
    kwargs.setdefault("metavar", "CURVES")
    return parser.add_argument(*TONES_OPTION, dest=dest, action=OneCurve, **kwargs)


class OneCurve(argparse._StoreAction):
    """The curve option's value, given under any of its spellings: ``--tone hable --curve aces`` would keep the
    last silently, so two that name different curves are a usage error naming both (the same curves, in any
    case, with ``_`` or ``-``, are taken once)."""

    what = "curves"

    @staticmethod
    def key(value):
        return _curve_key(value)

    def __call__(self, parser, namespace, values, option_string=None):
        given = namespace.__dict__.setdefault("_curves_given", {})
        before = given.get(self.dest)
        if before is not None and self.key(before[1]) != self.key(values):
            parser.error(f"{before[0]} {before[1]} and {option_string} {values} name different {self.what}; give one")
        given[self.dest] = (option_string, values)
        setattr(namespace, self.dest, values)


class OneFormat(OneCurve):
    """An output-format option with two spellings (``--to``, ``--format``): ``--to jpg --format png`` is a usage
    error naming both, as two curves are; the same format twice is taken."""

    what = "formats"

    @staticmethod
    def key(value):
        return str(value).lower()


def _curve_key(value) -> list[str]:
    """Curve names as the tone registry compares them (:func:`lenslab.tone.registry.curve_key`), a list by its
    commas."""
    from lenslab.tone.registry import curve_key

    return [curve_key(name) for name in str(value).split(",")]


def add_tone_mode_option(parser, per_channel_help: str, luminance_help: str) -> None:
    """Declare ``--per-channel`` (the default) and ``--luminance``, one or the other, into ``args.mode`` as
    :func:`lenslab.tone.tonemap` takes it; each command words their help for what it does with the curve."""
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--per-channel", dest="mode", action="store_const", const="per-channel", help=per_channel_help)
    group.add_argument("--luminance", dest="mode", action="store_const", const="luminance", help=luminance_help)
    parser.set_defaults(mode="per-channel")


def non_empty(text: str) -> str:
    """argparse ``type=``: a name, spec or file that is not blank; an empty one would silently mean the
    option's default (``--tone ''`` hable, ``--from ''`` the file's own camera)."""
    if not text.strip():
        raise argparse.ArgumentTypeError("is empty; give a value, or leave the option out for its default")
    return text


def finite_float(text: str) -> float:
    """argparse ``type=``: any finite number (angles such as ``--yaw``); NaN and inf are refused."""
    try:
        x = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{str(text)[:40]!r} is not a number") from None
    if not math.isfinite(x):
        raise argparse.ArgumentTypeError(f"{str(text)[:40]!r}: must be a finite number")
    return x


def float_in(low: float, high: float):
    """argparse ``type=`` factory: a finite number above ``low`` and at most ``high`` (e.g. ``--rate``)."""

    def parse(text: str) -> float:
        x = finite_float(text)
        if not (low < x <= high):
            raise argparse.ArgumentTypeError(f"{str(text)[:40]!r}: must be above {low:g} and at most {high:g}")
        return x

    return parse


def finite_vector(text: str) -> tuple[float, float, float]:
    """argparse ``type=``: ``X,Y,Z`` of three finite numbers (``--look-at``, ``--eye``)."""
    parts = str(text).split(",")
    try:
        v = tuple(float(p) for p in parts)
    except ValueError:
        v = ()
    if len(v) != 3 or not all(math.isfinite(c) for c in v):
        raise argparse.ArgumentTypeError(f"{str(text)[:40]!r}: give X,Y,Z as three finite numbers, e.g. 0,1,0")
    return v


def positive_float(text: str) -> float:
    """argparse ``type=``: a finite number above 0 (``--time-budget``, ``--target-error``)."""
    try:
        x = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not (x > 0 and x != float("inf")):
        raise argparse.ArgumentTypeError(f"{text!r}: must be a finite number above 0")
    return x


def int_in(low: int, high: int | None = None):
    """argparse ``type=`` factory: a whole number from ``low`` (to ``high``), e.g. ``--quality``."""

    def parse(text: str) -> int:
        try:
            n = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
        if n < low or (high is not None and n > high):
            raise argparse.ArgumentTypeError(f"{text!r}: must be from {low} to {high}" if high is not None
                                             else f"{text!r}: must be at least {low}")
        return n

    return parse


positive_int = int_in(1)  # --jobs, --spp, --samples
non_negative_int = int_in(0)  # --max-depth, or a count where 0 means "no limit"


def image_size(text: str) -> tuple[int, int]:
    """argparse ``type=``: ``WxH`` with both sides at least 1, e.g. ``1024x512``."""
    parts = str(text).lower().replace("*", "x").split("x")
    try:
        w, h = (int(p) for p in parts)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not WIDTHxHEIGHT, e.g. 1024x512") from None
    if w < 1 or h < 1:
        raise argparse.ArgumentTypeError(f"{text!r}: width and height must be at least 1 pixel")
    from lenslab.inputs.limits import MAX_PIXELS

    if w * h > MAX_PIXELS:  # the cap every image size meets (LENSLAB_MAX_PIXELS)
        raise argparse.ArgumentTypeError(f"{text!r}: more than {MAX_PIXELS:,} pixels (LENSLAB_MAX_PIXELS); give a "
                                         "smaller size")
    return w, h


def parse_exposure(text: str) -> float | str:
    """``--exposure``: a number of stops, or ``"auto"``; anything else is a ToneError that says so."""
    if str(text).strip().lower() == "auto":
        return "auto"
    try:
        ev = float(text)
    except ValueError:
        ev = math.nan
    if not math.isfinite(ev):
        from lenslab.errors import ToneError

        raise ToneError(f"--exposure must be a number of stops or 'auto', not {str(text)[:40]!r}") from None
    return ev


def add_jobs_option(parser, what: str = "files") -> None:
    """``--jobs N`` of a batch on this machine: how many ``what`` at once on threads of the process."""
    parser.add_argument("--jobs", "-j", type=non_negative_int, default=0, metavar="N",
                        help=f"how many {what} at once on this machine (default 0: one per CPU core, as many as the "
                             "memory holds judging by the first file; 1: one after the other, each on every core)")


def check_skip_or_overwrite(args) -> None:
    """``--skip-existing`` and ``--overwrite`` say opposite things of an existing output: a usage error."""
    if getattr(args, "skip_existing", False) and getattr(args, "overwrite", False):
        raise UsageError("--skip-existing leaves existing outputs alone and --overwrite replaces them: give one")


def add_scheduler_options(parser, skip_existing: bool = True) -> None:
    """``--scheduler``, ``--scheduler-file`` (and ``--skip-existing``) of every batch command: one task
    per file on a Dask cluster (:mod:`lenslab.cluster`)."""
    group = parser.add_argument_group("running on a Dask cluster (see docs/guide/batches.md)")
    group.add_argument("--scheduler", metavar="ADDRESS", default=None,
                       help="run the work on the Dask cluster whose scheduler is at ADDRESS (e.g. "
                            "tcp://host:8786), one task per file (per tile for a render); default: "
                            "$DASK_SCHEDULER_ADDRESS, else this machine. The workers must see the same files")
    group.add_argument("--scheduler-file", metavar="FILE", default=None,
                       help="the same, with the address read from the file 'dask scheduler --scheduler-file' wrote")
    group.add_argument("--scheduler-timeout", type=float_in(0, 3600), default=15.0, metavar="SECONDS",
                       help="give up on a scheduler that does not answer within this time (default 15)")
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


def typed(args, dest: str, default: str) -> str:
    """The spelling under which a curve or format option ``dest`` was given (``--curve`` or ``--tone``), for the
    messages about it; ``default`` where it was not given."""
    return args.__dict__.get("_curves_given", {}).get(dest, (default,))[0]


def check_tone_applies(flag: str, given: bool, display: str | None, outputs) -> None:
    """A tone curve named on the command line (``given``) must have something to do: refused with
    ``--display`` (an OpenColorIO view maps scene light itself) and for outputs that keep linear light.
    ``outputs``: ``(name, why)`` for each output that keeps linear light (why it does)."""
    if not given:
        return
    if display:
        raise UsageError(f"{flag} and --display both map scene light to the display: give one (--display "
                         "with --view 'ACES 2.0 - SDR' tone-maps as it transforms)")
    for name, why in outputs:
        raise UsageError(f"{flag} applies to display formats (PNG, JPG, PPM); {name}: {why}")


def check_frames_apply(frames, stills) -> None:
    """``--frames`` picks frames of videos: a usage error when an input (of ``stills``) is a still image."""
    for still in stills:
        raise UsageError(f"--frames picks frames of a video; {still} is a still image")
