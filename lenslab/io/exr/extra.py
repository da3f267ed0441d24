"""The channels of an EXR part that are not in the image lenslab reads (depth ``Z``, normals ``N.x``,
motion vectors, other layers): named for a note, and kept as planes for an EXR writer.

Each plane keeps its stored type (half, float or uint), is upsampled like the image's channels when
subsampled, and is placed in the display window as the image is (outside the data window: 0), or kept
in the data window with ``data_window=True``, which a convert from EXR to EXR reads them with so that it
writes them back where they were (no 0 made up outside the stored pixels).
"""

from __future__ import annotations

import numpy as np

from lenslab.errors import FormatError, clip
from lenslab.io.exr.colour import upsample


def extra_names(names: list[str], used: set[str]) -> list[str]:
    """The part's channel names (file order) not in ``used`` (the full names the image was made of)."""
    return [n for n in names if n not in used]


def extra_planes(path, chans, names: list[str], sampling: dict, window, placed_in) -> dict[str, np.ndarray]:
    """``{name: H x W plane}`` of the channels ``names`` from the bindings' ``chans``. ``window``: the data
    window ``(x0, y0, x1, y1)``; ``placed_in``: the display window to place the planes in, or None to keep
    the data window's pixels as they are."""
    x0, y0, x1, y1 = window
    w, h = x1 - x0 + 1, y1 - y0 + 1
    out = {}
    for name in names:
        ch = chans.get(name)
        if ch is None or ch.pixels is None or ch.pixels.dtype == object:
            continue  # deep or missing: nothing flat to keep
        pix = ch.pixels
        xs, ys = sampling.get(name, (1, 1))
        if (xs, ys) != (1, 1):
            pix = upsample(pix, xs, ys, w, h, x0, y0).astype(ch.pixels.dtype)
        if pix.shape != (h, w):
            raise FormatError(f"{path}: channel {clip(name)} is {pix.shape[1]} x {pix.shape[0]}, not the data "
                              f"window's {w} x {h}; the file is damaged")
        if placed_in is not None and tuple(placed_in) != tuple(window):
            from lenslab.io.exr.whole import placed

            pix = placed(pix, window, placed_in)
        out[name] = np.ascontiguousarray(pix)
    return out


class DroppedChannelsWarning(UserWarning):
    """Channels of the input (depth, normals...) that the output's format cannot hold were not written.
    ``command_line`` is the note without the path (a command's note names the file)."""


def clashing(extra: list[str], written: list[str]) -> list[str]:
    """The extra channels an EXR cannot keep beside the image's: those named as one of the image's
    ``written`` channels (the base ``R, G, B`` of a file whose layer ``left`` is written as ``R, G, B``)."""
    return [n for n in extra if n in set(written)]


def warn_dropped(path, names: list[str], target: str, why: str | None = None) -> None:
    """Say in one line that ``names`` were not written to a ``target`` file (nothing when there are none);
    ``why``: the reason (default: the format holds colour and alpha only)."""
    if not names:
        return
    import warnings

    shown = ", ".join(clip(n) for n in names[:12]) + (f" and {len(names) - 12} more" if len(names) > 12 else "")
    why = why or f"{target} holds colour and alpha only (write EXR to keep them)"
    note = f"channel(s) {shown} not written: {why}"
    warning = DroppedChannelsWarning(f"{path}: {note}")
    warning.command_line = note
    warnings.warn(warning, stacklevel=3)
