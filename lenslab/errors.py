"""The project's own exception types.

Every error a user can cause is one of these, and its message says what was wrong and what to do.
They subclass the built-in type a caller would expect (ValueError for bad values, OSError stays
OSError), so ``except ValueError`` keeps working.
"""

from __future__ import annotations

import contextlib
from _thread import get_ident

#: NumPy's arithmetic notes (NaN or inf met in a cast, a division, a log) are the commands' business to
#: handle and report in the user's terms; they never reach the terminal as library warnings.
NUMPY_NOTES = r"(invalid value|overflow|divide by zero|underflow) encountered"


#: the stop signals received while a command runs, recorded by the handlers of the error funnel
#: (:func:`lenslab.jobs.funnel.stop_signals`); cleared when a command starts
RECEIVED_SIGNALS: list[int] = []


def stop_signal(exc: BaseException | None = None) -> int | None:
    """The number of the stop signal that ``exc`` comes from: a KeyboardInterrupt (or the funnel's
    ``Interrupted``, which carries ``signum``) itself or in its chain of causes, or any error once the command
    has received a stop signal (whatever is raised after a Ctrl-C is the command ending); None for an error
    of its own. A Ctrl-C that lands inside ``threading.Condition.wait`` (a pool's or a progress bar's wait)
    can leave its lock released, and what reaches the caller is then a RuntimeError ("release unlocked
    lock"), not the KeyboardInterrupt: wherever errors are caught, this tells the interrupt from a failure."""
    import signal

    seen = set()
    while exc is not None and id(exc) not in seen:
        if isinstance(exc, KeyboardInterrupt):
            return int(getattr(exc, "signum", signal.SIGINT))
        seen.add(id(exc))
        exc = exc.__cause__ or exc.__context__
    return RECEIVED_SIGNALS[0] if RECEIVED_SIGNALS else None


#: per thread (by id): how deep it is in :func:`stop_signals_held` blocks, and the stop it has held back
_HELD_DEPTH: dict[int, int] = {}
_HELD_STOP: dict[int, BaseException] = {}


@contextlib.contextmanager
def stop_signals_held():
    """A block that a stop signal does not cut in two: the exception of a stop signal received inside it (in
    the main thread, where Python runs signal handlers) is raised when the outermost such block ends, after its
    clean-up. For work whose half-done state outlives the exception, such as file descriptors pointed
    elsewhere for a library call (:mod:`lenslab.library_output`): an exception between two of its steps would
    leave standard error pointed at a temporary file, and the command's last line would go there. Blocks nest;
    elsewhere than in the main thread they change nothing."""
    me = get_ident()
    _HELD_DEPTH[me] = _HELD_DEPTH.get(me, 0) + 1  # from here on, a stop waits for the end of the block
    try:
        yield
    finally:
        depth = _HELD_DEPTH[me] - 1
        if depth:
            _HELD_DEPTH[me] = depth  # (held all along: the outer block ends it)
        else:
            del _HELD_DEPTH[me]
            held = _HELD_STOP.pop(me, None)  # (a stop landing from here on is raised by its handler at once)
            if held is not None:
                raise held


def hold_stop(exc: BaseException) -> bool:
    """For a stop signal's handler: True if this thread is inside :func:`stop_signals_held`, where ``exc`` is kept
    (the first stop received) to be raised at the block's end; False if the handler is to raise ``exc`` now."""
    me = get_ident()
    if _HELD_DEPTH.get(me):
        _HELD_STOP.setdefault(me, exc)
        return True
    _HELD_STOP.pop(me, None)  # raised now: nothing is left to raise later
    return False


class LenslabError(Exception):
    """Base of every lenslab error (mixed into a built-in type below)."""


class FormatError(LenslabError, ValueError):
    """A file's content is not a valid image of the format it claims, or cannot be written so."""


class LensError(LenslabError, ValueError):
    """A lens or camera specification is invalid (unknown model, parameter or value out of range)."""


class ToneError(LenslabError, ValueError):
    """An unknown tone curve, or a curve parameter out of range."""


class WarpError(LenslabError, ValueError):
    """A warp cannot be done as asked (incompatible cameras, parallax, bad sizes)."""


class FitError(LenslabError, ValueError):
    """A fit could not be set up or did not converge; carries the best point found when there is one."""

    def __init__(self, message: str, best=None):
        super().__init__(message)
        self.best = best


class FitSpecError(FitError, LensError):
    """A fit asked for in terms that name nothing: an unknown model or parameter in the spec, ``--free`` or
    ``--bounds``. A lens spec error, so a usage error (exit 2) when it was typed on the command line."""


class UsageError(LenslabError):
    """A bad option, spec or value given on the command line: exit code 2, one line, before any work."""


class OutputError(LenslabError, OSError):
    """An output that may not be written: it exists (no ``--overwrite``), it is one of the inputs, or it
    is not a regular file (a FIFO or a device is never replaced)."""


class ImageShapeError(FormatError, WarpError, FitError):
    """An array that is not an image: not H x W or H x W x C, empty, not numbers, or a channel count the
    operation does not take. One type for every stage (reading, writing, warping, fitting, measuring);
    it is each stage's own error type too, so callers that catch those keep working."""


def check_image_shape(array, what: str = "the image", channels=(1, 2, 3, 4)):
    """``array`` as a NumPy array if it is an image: H x W or H x W x C of numbers, H and W at least 1,
    C in ``channels`` (None: any). Raises :class:`ImageShapeError` naming ``what``. The array is returned
    as it is (no copy, no added axis)."""
    import numpy as np

    a = np.asarray(array)
    if a.ndim not in (2, 3) or a.shape[0] < 1 or a.shape[1] < 1 or (a.ndim == 3 and a.shape[2] < 1):
        raise ImageShapeError(f"{what} must be an H x W or H x W x C image, got an array of shape {a.shape}")
    if a.dtype.kind not in "fiub":
        raise ImageShapeError(f"{what} must hold numbers, got an array of {a.dtype}")
    if channels is not None and a.ndim == 3 and a.shape[2] not in channels:
        raise ImageShapeError(f"{what} has {a.shape[2]} channels; give {', '.join(map(str, channels))}")
    return a


class InputError(LenslabError, ValueError):
    """An input file cannot be read safely: not a regular file, larger than its limit, nested too deep,
    or declaring more than its bytes can hold. A failed input (exit status 1), never a crash."""


def clip(value, limit: int = 40) -> str:
    """A value from a file, as text cut to ``limit`` characters, for error messages (a hostile file
    must not make a message long, nor expand an alias bomb while describing it)."""
    if isinstance(value, (dict, list, tuple, set)):
        return f"a {type(value).__name__} of {len(value)} item(s)"
    if isinstance(value, (str, bytes)):
        text = repr(value[:limit + 1])
    else:
        try:
            text = repr(value)
        except Exception:  # noqa: BLE001 - a value that cannot even describe itself
            text = f"<{type(value).__name__}>"
    return text if len(text) <= limit else text[:limit - 3] + "..."


def cause(exc: BaseException | str, limit: int = 80) -> str:
    """An exception of a library (or its text) as a few words for a message: its first line, cut to at
    most ``limit`` characters after a whole word."""
    lines = str(exc).strip().splitlines()
    text = lines[0].strip() if lines else type(exc).__name__
    if len(text) <= limit:
        return text
    cut = text[:limit - 3].rstrip()
    space = cut.rfind(" ")
    return (cut[:space].rstrip(" ,;:(") if space > 0 else cut) + "..."
