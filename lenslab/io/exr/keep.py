"""What an EXR written from an EXR keeps of the input's header, as a compositor (or ``oiiotool``) would.

- The data and display windows: the stored pixels are written where they were, outside the data window
  nothing (a reader gives 0 there, as for the input), so a depth ``Z`` is never given a 0 it did not have.
"""

from __future__ import annotations


def kept_header(path, meta: dict, written: list[str]) -> dict:
    """The write options that keep ``meta``'s part header (``meta``: what :func:`lenslab.io.read` gave for
    an EXR read with ``data_window=True``; ``written``: every channel name to be written): ``window``
    (the data and display windows)."""
    return {"window": (meta["data_window"], meta["display_window"])}
