"""Slight negative values: a lossy codec's undershoot, counted once per command instead of per file.

Tone mapping sets negative values to 0. Most negatives in real files are no error of the scene: the
lossy EXR codecs (DWAA/DWAB, B44, PXR24) and the ringing of a resampling filter leave values a little
below 0 next to black (DWAB: about -4e-4). Those are counted here, in one tally for the whole process,
and a command reports them in one line at its end (:func:`take_summary`); they are never a Python
warning. NaN, +inf and negatives below :data:`SLIGHT` are real damage or real negative light (a wrong
colour space, a subtraction) and stay a :class:`~lenslab.tone.ToneWarning` per image.

Why ``SLIGHT = 2**-10`` (9.8e-4 of white): it is one half-float step at 1.0, the precision EXR's
half holds near white; a lossy half codec quantises a block relative to its brightest values, so its
undershoot next to a bright value stays within about that step, while negative light from a colour
conversion or a subtraction is a sizeable fraction of the signal. Once sRGB-encoded it is about three
8-bit code values below black: invisible on a display, which clips at 0 anyway.
"""

from __future__ import annotations

import threading

#: negatives down to -SLIGHT are a codec's or filter's undershoot (see the module docstring)
SLIGHT = 2.0 ** -10

_lock = threading.Lock()
_tally = {"values": 0, "images": 0, "lowest": 0.0}


def add(count: int, lowest: float) -> None:
    """Count ``count`` slight negatives (the lowest ``lowest``) repaired in one image."""
    with _lock:
        _tally["values"] += int(count)
        _tally["images"] += 1
        _tally["lowest"] = min(_tally["lowest"], float(lowest))


def take() -> tuple[int, int, float]:
    """``(values, images, lowest)`` counted since the last call, and the tally reset."""
    with _lock:
        out = (_tally["values"], _tally["images"], _tally["lowest"])
        _tally.update(values=0, images=0, lowest=0.0)
    return out


def take_summary() -> str | None:
    """One line for a command's end, or None when nothing was repaired (the tally is reset)."""
    values, images, lowest = take()
    if not values:
        return None
    return (f"tone mapping set {values} slightly negative value{'s' if values != 1 else ''} (down to "
            f"{lowest:.2g}, a lossy codec's or filter's undershoot) to 0 in {images} image{'s' if images != 1 else ''}")


#: how a cluster task hands its tally to the command that reports it (a note the command parses back)
_NOTE = "slight negatives repaired:"


def take_note() -> str | None:
    """This process's tally as a note for another process (a cluster worker's task), and the tally reset."""
    values, images, lowest = take()
    return f"{_NOTE}{values}:{images}:{lowest!r}" if values else None


def absorb_note(note: str) -> bool:
    """Add a worker's :func:`take_note` to this process's tally; False for any other note."""
    if not note.startswith(_NOTE):
        return False
    values, images, lowest = note[len(_NOTE):].split(":")
    with _lock:
        _tally["values"] += int(values)
        _tally["images"] += int(images)
        _tally["lowest"] = min(_tally["lowest"], float(lowest))
    return True
