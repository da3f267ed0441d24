"""The one output policy and the exit codes of every command (``lenslab``, ``tracer``, ``python -m gallery``).

Outputs:

- an existing file is replaced only with ``--overwrite``;
- an input is never written over, with or without ``--overwrite`` (the same path, or the same file
  reached through a link: compared by device and inode);
- every file is written to a temporary name and renamed (:func:`lenslab.io.atomic.atomic_write_path`);
- a batch checks what does not depend on one file before it touches anything, and creates no output
  folder when it cannot start (:func:`check_output_dir` only says what it would create).

Exit codes (:func:`run_command`): 0 all done; 1 some inputs failed; 2 a usage error (a bad option,
spec or value: one line, no usage dump); 130 interrupted. A closed pipe (``lenslab info F | head -1``)
ends the command quietly with the code the shell expects of a reader that went away (0).

Standard library only: every command's parser module imports this, and ``--help`` stays instant.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import re
import sys
import warnings
from pathlib import Path
from typing import Callable, Iterable

EXIT_OK, EXIT_FAILED, EXIT_USAGE, EXIT_INTERRUPTED = 0, 1, 2, 130


class UsageError(Exception):
    """A bad option, spec or value given on the command line: exit code 2, one line."""


class OutputError(OSError):
    """An output that may not be written: it exists (no ``--overwrite``) or it is one of the inputs."""


class ArgumentParser(argparse.ArgumentParser):
    """argparse with one-line errors: ``PROG: error: MESSAGE (see PROG --help)``, exit code 2.

    A bad value is reported by its option's ``type=`` function (an ``argparse.ArgumentTypeError``
    whose message says what is expected); argparse's usage dump is left for ``--help``.
    """

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        # No option starts with a digit: "-100x100" or "-3e-5" after an option is its (bad or negative)
        # value, for the option's type to judge, not an unknown option.
        self._negative_number_matcher = re.compile(r"^-\.?\d")

    def error(self, message: str):  # noqa: D401 - argparse's hook
        print(f"{self.prog}: error: {message} (see '{self.prog} --help')", file=sys.stderr)
        raise SystemExit(EXIT_USAGE)


def same_file(a: str | os.PathLike, b: str | os.PathLike) -> bool:
    """Whether ``a`` and ``b`` name the same existing file (same device and inode, links followed)."""
    try:
        return os.path.samefile(a, b)
    except OSError:
        return False


def check_output(path: str | os.PathLike, inputs: Iterable[str | os.PathLike] = (), overwrite: bool = False) -> Path:
    """Refuse to write ``path`` when it is one of ``inputs`` (always) or exists (unless ``overwrite``).

    Raises :class:`OutputError`; returns ``path`` as a :class:`~pathlib.Path`. Nothing is written.
    """
    out = Path(path)
    for src in inputs:
        src = str(src)
        if ":" in src and not os.path.exists(src):  # an EXR part or layer selector: file.exr:left
            src = src.rpartition(":")[0]
        if same_file(out, src) or (Path(src).absolute() == out.absolute()):
            raise OutputError(f"{out}: is an input of this command; it is never written over, even with "
                              "--overwrite: choose another output name")
    if out.is_dir():
        raise UsageError(f"{out}: is a folder; give a file name to write to")
    if out.exists() and not overwrite:
        raise OutputError(f"{out}: already exists; give --overwrite to replace it")
    if not out.parent.is_dir() and str(out.parent) not in ("", "."):
        raise OutputError(f"{out}: the folder {out.parent} does not exist")
    return out


def check_output_dir(path: str | os.PathLike, inputs: int | None = None) -> Path:
    """Check that ``path`` can be an output folder (an existing folder, or a new one whose parent can be
    made); create nothing. Call :func:`make_output_dir` once everything else has been checked. With
    ``inputs`` (how many files go there), a new name with an image extension is taken for a file name
    given by mistake: a usage error."""
    out = Path(path)
    if inputs is not None and not out.is_dir():
        from lenslab.io.registry import input_extensions

        if out.suffix.lower() in input_extensions():
            raise UsageError(f"-o {out} names a file but there are {inputs} inputs; give a folder")
    if out.exists() and not out.is_dir():
        raise UsageError(f"{out}: exists and is not a folder; give a folder for several outputs")
    parent = out.absolute().parent
    while not parent.exists():
        parent = parent.parent
    if not parent.is_dir() or not os.access(parent, os.W_OK):
        raise OutputError(f"{out}: cannot be created in {parent}")
    return out


def output_format(path: str | os.PathLike) -> str:
    """The output format an output name asks for; an unknown extension is a usage error (checked before
    any input is read)."""
    from lenslab.errors import FormatError
    from lenslab.io.detect import format_for_path

    try:
        return format_for_path(path)
    except FormatError as exc:
        raise UsageError(str(exc)) from None


def make_output_dir(path: str | os.PathLike) -> Path:
    out = check_output_dir(path)
    out.mkdir(parents=True, exist_ok=True)
    return out


# NumPy's arithmetic notes (NaN or inf met in a cast, a division, a log) are the commands' business to
# handle and report in the user's terms; they never reach the terminal as library warnings.
_NUMPY_NOTES = r"(invalid value|overflow|divide by zero|underflow) encountered"


def user_notes(caught) -> list[str]:
    """The distinct messages of recorded warnings a user should read (NumPy's arithmetic notes left out),
    in the commands' words where a warning carries them (``command_line``)."""
    notes = (getattr(w.message, "command_line", None) or str(w.message) for w in caught
             if not (issubclass(w.category, RuntimeWarning) and re.search(_NUMPY_NOTES, str(w.message))))
    return list(dict.fromkeys(notes))


def run_command(prog: str, func: Callable[[], int | None]) -> int:
    """Run ``func`` under the exit-code policy; print one line for an error. Returns the exit code."""
    from lenslab.errors import LenslabError, LensError, ToneError

    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=_NUMPY_NOTES, category=RuntimeWarning)
        try:
            code = int(func() or 0)
            sys.stdout.flush()
            _print_repairs(prog)
            return code
        except KeyboardInterrupt:
            print(f"{prog}: interrupted", file=sys.stderr)
            return EXIT_INTERRUPTED
        except BrokenPipeError:
            return _closed_pipe()
        except UsageError as exc:
            print(f"{prog}: error: {exc}", file=sys.stderr)
            return EXIT_USAGE
        except (LensError, ToneError) as exc:  # a lens spec or a tone curve given on the command line
            print(f"{prog}: error: {one_line(exc)}", file=sys.stderr)
            return EXIT_USAGE
        except (LenslabError, OSError, ValueError) as exc:
            if isinstance(exc, OSError) and exc.errno == 32:  # EPIPE raised by a writer as a plain OSError
                return _closed_pipe()
            print(f"{prog}: error: {one_line(exc)}", file=sys.stderr)
            return EXIT_FAILED
        except MemoryError:
            print(f"{prog}: error: out of memory; try a smaller --size", file=sys.stderr)
            return EXIT_FAILED


def _print_repairs(prog: str) -> None:
    """The command's one line on slight negatives repaired by tone mapping (lenslab.tone.repairs), if any."""
    if "lenslab.tone.repairs" not in sys.modules:  # nothing was tone-mapped
        return
    from lenslab.tone.repairs import take_summary

    line = take_summary()
    if line:
        print(f"{prog}: note: {line}", file=sys.stderr)


def one_line(exc: BaseException) -> str:
    """The error's message on one line; an operating-system error as ``path: reason`` (no errno)."""
    if isinstance(exc, OSError) and exc.filename is not None and exc.strerror and type(exc) is not OutputError:
        return f"{exc.filename}: {exc.strerror[:1].lower()}{exc.strerror[1:]}"
    text = str(exc).strip() or type(exc).__name__
    return " ".join(text.split("\n")[0].split()) if "\n" in text else text


@contextlib.contextmanager
def library_output_to_stderr():
    """Send what C libraries print on standard output (OpenEXR's warnings about a damaged file) to
    standard error for the duration, so a report written on standard output stays clean. Process-wide:
    for commands that read one file at a time."""
    sys.stdout.flush()
    try:
        saved = os.dup(1)
    except OSError:  # no standard output to protect
        yield
        return
    try:
        os.dup2(2, 1)
        yield
    finally:
        sys.stdout.flush()
        os.dup2(saved, 1)
        os.close(saved)


def _closed_pipe() -> int:
    """The reader went away: point stdout at /dev/null so the interpreter's final flush stays quiet."""
    with contextlib.suppress(OSError, ValueError):
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    return EXIT_OK


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
    if w * h > 1 << 28:
        raise argparse.ArgumentTypeError(f"{text!r}: more than 268 million pixels; give a smaller size")
    return w, h
