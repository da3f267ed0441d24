"""The one error funnel of every command (``lenslab``, ``tracer``, ``python -m gallery``): whatever goes
wrong becomes one line on standard error that names the file and the cause, and an exit code.

Exit codes (:func:`run_command`): 0 all done; 1 an input failed; 2 a usage error (a bad option, spec or
value: one line, no usage dump); 130, 143, 129 interrupted by Ctrl-C, SIGTERM (``kill``, ``timeout``,
SLURM) or SIGHUP (the terminal went away): all three end the command the same way, temporaries removed.
A closed pipe (``lenslab info F | head -1``) ends the command quietly with 0. The traceback is printed
only under ``--debug``.

Standard library only: every command's parser module imports this, and ``--help`` stays instant.
"""

from __future__ import annotations

import contextlib
import errno
import os
import re
import signal
import sys
import warnings
from typing import Callable, Iterator

from lenslab.errors import (NUMPY_NOTES, RECEIVED_SIGNALS, LensError, LenslabError, OutputError, ToneError, UsageError,
                            hold_stop, stop_signal)

EXIT_OK, EXIT_FAILED, EXIT_USAGE, EXIT_INTERRUPTED = 0, 1, 2, 130
#: the signals that end a command as Ctrl-C does, and their names in the one-line note
STOP_SIGNALS = {signal.SIGINT: "Ctrl-C", signal.SIGTERM: "SIGTERM", signal.SIGHUP: "SIGHUP"}


class Interrupted(KeyboardInterrupt):
    """SIGTERM or SIGHUP, raised in the main thread like Ctrl-C so every clean-up path (temporaries,
    cancelled cluster tasks) runs the same way; the exit code is 128 + the signal's number."""

    def __init__(self, signum: int):
        super().__init__(STOP_SIGNALS.get(signum, f"signal {signum}"))
        self.signum = signum


_NUMPY_NOTES = NUMPY_NOTES


class CommandNote(UserWarning):
    """A note on the whole command, the same for each of its files (``--antialias`` on a view that shrinks the
    source nowhere): a batch prints it once, with the first of its files that gave it, whether the files ran on
    threads of this process or on any number of cluster workers (:func:`command_note`)."""


#: how a file's notes carry a :class:`CommandNote` to the command that prints them (a worker's notes are strings)
_COMMAND_NOTE = "note of the command: "


def user_notes(caught) -> list[str]:
    """The distinct messages of recorded warnings a user should read (NumPy's arithmetic notes left out),
    in the commands' words where a warning carries them (``command_line``); a :class:`CommandNote` marked
    for :func:`command_note`."""
    notes = ((_COMMAND_NOTE if issubclass(w.category, CommandNote) else "")
             + (getattr(w.message, "command_line", None) or str(w.message)) for w in caught
             if not (issubclass(w.category, RuntimeWarning) and re.search(_NUMPY_NOTES, str(w.message))))
    return list(dict.fromkeys(notes))


def command_note(note: str) -> str | None:
    """The text of a note of :func:`user_notes` that came from a :class:`CommandNote`, else None."""
    return note[len(_COMMAND_NOTE):] if note.startswith(_COMMAND_NOTE) else None


@contextlib.contextmanager
def working_on(path) -> Iterator[None]:
    """Mark the exceptions raised inside as this file's: the funnel's line then names it."""
    try:
        yield
    except BaseException as exc:
        if getattr(exc, "lenslab_file", None) is None:
            with contextlib.suppress(AttributeError, TypeError):
                exc.lenslab_file = str(path)
        raise


@contextlib.contextmanager
def stop_signals() -> Iterator[None]:
    """SIGTERM and SIGHUP raise :class:`Interrupted` in the main thread for the duration, Ctrl-C raises
    KeyboardInterrupt as Python's own handler does; each is recorded for :func:`stop_signal`. A signal the
    command was started with ignored (``nohup``) stays ignored, and a Ctrl-C handler of the program that calls
    the command is kept; elsewhere than in the main thread, nothing changes. The record goes with the handlers:
    after the block, an error is an error again."""
    import threading

    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def stop(signum, frame):
        RECEIVED_SIGNALS.append(signum)
        exc = KeyboardInterrupt() if signum == signal.SIGINT else Interrupted(signum)
        if not hold_stop(exc):  # (inside a block a stop must not cut in two, it is raised at the block's end)
            raise exc

    saved = {}
    for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
        current = signal.getsignal(sig)
        if current is signal.SIG_IGN or (sig == signal.SIGINT and current is not signal.default_int_handler):
            continue  # ignored by whoever started us (nohup), or Ctrl-C handled by the program that calls us
        with contextlib.suppress(OSError, ValueError):
            saved[sig] = signal.signal(sig, stop)
    try:
        yield
    finally:
        for sig, handler in saved.items():
            signal.signal(sig, handler)
        RECEIVED_SIGNALS.clear()  # (after the handlers: one landing before this is forgotten too)


def run_command(prog: str, func: Callable[[], int | None], debug: bool = False) -> int:
    """Run ``func`` under the exit-code policy; print one line for an error (and the traceback with
    ``debug``). Returns the exit code."""
    with warnings.catch_warnings(), stop_signals():
        warnings.filterwarnings("ignore", message=_NUMPY_NOTES, category=RuntimeWarning)
        warnings.showwarning = note_printer(prog)
        _forget_repairs()  # the command reports its own repairs, not those of earlier calls in this process
        _SAID.clear()
        RECEIVED_SIGNALS.clear()
        try:
            code = int(func() or 0)
            sys.stdout.flush()
            _print_repairs(prog)
            return code
        except BrokenPipeError:
            return _closed_pipe()
        except SystemExit:
            raise
        except BaseException as exc:  # noqa: BLE001 - the funnel: every error is one line
            signum = stop_signal(exc)  # Ctrl-C, also when it reached us as another error (see stop_signal)
            if signum is not None:
                print(f"{prog}: interrupted ({STOP_SIGNALS.get(signum, signum)}); unfinished outputs removed",
                      file=sys.stderr)
                return 128 + int(signum)
            if isinstance(exc, OSError) and exc.errno == 32:  # EPIPE raised by a writer as a plain OSError
                return _closed_pipe()
            if not isinstance(exc, Exception) and type(exc).__name__ != "CancelledError":
                raise  # GeneratorExit and the like are the interpreter's business
            if debug:
                import traceback

                traceback.print_exc()
            print(f"{prog}: error: {one_line(exc)}", file=sys.stderr)
            return exit_code(exc)
        finally:  # a later call of the library in this process (a notebook) starts with no signal received
            RECEIVED_SIGNALS.clear()
            opened = sys.modules.get("lenslab.io.video.opened")
            if opened is not None:  # a clip probed and not decoded: its file closed with the command
                opened.release(every=True)


def _forget_repairs() -> None:
    """Reset the process's tally of repaired slight negatives (only when the tone package is loaded: a
    command that never tone-maps does not import it for this)."""
    repairs = sys.modules.get("lenslab.tone.repairs")
    if repairs is not None:
        repairs.take()


def report_missing(prog: str, missing) -> None:
    """One error line per input that names no file (``(input, reason)`` of
    :func:`lenslab.jobs.plan.expand_inputs`), in the form of every other error: ``PROG: error: IN: reason``."""
    for pat, reason in missing:
        print(f"{prog}: error: {cut(f'{pat}: {reason}')}", file=sys.stderr)


#: the words of the notes the command printed as they came (:func:`note_printer`)
_SAID: set[str] = set()


def said(note: str) -> bool:
    """Whether the command printed ``note`` already, as it came (a camera file's note, given once as the options
    were read): the files that give it again do not repeat it."""
    return " ".join(note.split()) in _SAID


def note_printer(prog: str):
    """``warnings.showwarning`` of a command: a warning that reaches the terminal (a file's note, such as
    the parts of a multi-part EXR) is one line, ``PROG: note: MESSAGE``, never Python's warning with its
    source line. Batch commands record each file's warnings as its notes (:func:`user_notes`) and print them
    in the same form."""

    def show(message, category, filename, lineno, file=None, line=None):
        text = " ".join(str(message).split()) or category.__name__
        _SAID.add(text)
        print(f"{prog}: note: {cut(text)}", file=sys.stderr)

    return show


def _print_repairs(prog: str) -> None:
    """The command's one line on slight negatives set to 0 (tone mapping, an RGBE output; lenslab.tone.repairs), if
    any."""
    if "lenslab.tone.repairs" not in sys.modules:  # nothing was tone-mapped
        return
    from lenslab.tone.repairs import take_summary

    line = take_summary()
    if line:
        print(f"{prog}: note: {line}", file=sys.stderr)


def exit_code(exc: BaseException) -> int:
    """2 for a usage mistake (a bad option, lens spec or tone curve given on the command line), else 1."""
    if isinstance(exc, UsageError):
        return EXIT_USAGE
    if isinstance(exc, (LensError, ToneError)) and getattr(exc, "lenslab_file", None) is None:
        return EXIT_USAGE  # a lens spec or a tone curve given on the command line
    return EXIT_FAILED


def one_line(exc: BaseException, limit: int = 400) -> str:
    """The error's message on one line, naming its file: an operating-system error as ``path: reason``
    (no errno), an unexpected one with its type; cut to ``limit`` characters."""
    file = getattr(exc, "lenslab_file", None)
    if isinstance(exc, MemoryError):
        text = "out of memory: the machine could not give what this input needs"
    elif isinstance(exc, OSError) and exc.filename is not None and exc.strerror and type(exc) is not OutputError:
        from lenslab.atomic import name_too_long

        text = (exc.errno == errno.ENAMETOOLONG and name_too_long(exc.filename)) or \
            f"{exc.filename}: {exc.strerror[:1].lower()}{exc.strerror[1:]}"
    else:
        text = " ".join((str(exc).strip() or type(exc).__name__).split("\n")[0].split())
        if not isinstance(exc, (LenslabError, OSError, ValueError)) or isinstance(exc, (RecursionError,)):
            text = f"{type(exc).__name__}: {text}" if text != type(exc).__name__ else text
    if file:
        text = naming(file, text)
    return cut(text, limit)


def naming(file: str, text: str) -> str:
    """``text`` naming ``file`` once: as it is when it names the file, else led by it; a message led by the
    file's path without the selector typed after it (``f.exr: part 5 ...`` for ``f.exr:5``) is led by what was
    typed instead of naming the file twice (a file that is not there keeps its path said)."""
    if file in text:
        return text
    head = text.split(": ", 1)[0]
    if head and file.startswith(head + ":") and os.path.isfile(head):
        return file + text[len(head):]
    return f"{file}: {text}"


_NAME = re.compile(r"[\w.+/'\"-]+(?: [\w.+/'\"-]+)?")  # a valid name as messages list them (one or two words)
LIST_LIMIT = 2000  # a message that ends in a list of valid names is shown whole up to this length


def cut(text: str, limit: int = 400) -> str:
    """``text`` cut to ``limit`` characters, except that a message ending in a list of names (``valid
    models: a, b, c``) keeps every name up to :data:`LIST_LIMIT` and beyond it is cut between two names,
    with ``and N more``."""
    if len(text) <= limit:
        return text
    start = text.rfind(": ", 0, limit)
    items = text[start + 2:].split(", ") if start >= 0 else []
    if len(items) < 3 or not all(_NAME.fullmatch(i) for i in items):
        return text[: limit - 3] + "..."
    if len(text) <= LIST_LIMIT:
        return text
    head, shown = text[: start + 2], []
    for i, item in enumerate(items):
        more = f" and {len(items) - i} more"
        if len(head) + len(", ".join(shown + [item])) + len(more) > LIST_LIMIT:
            return head + ", ".join(shown) + more
        shown.append(item)
    return text  # pragma: no cover - the loop returns once the list passes the limit


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
