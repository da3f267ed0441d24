"""Lens specs that name something other than a model, and the readers that claim them.

:func:`lenslab.lenses.make_lens` asks these before it parses ``name:key=value``. The layers above the
lens models add theirs (:mod:`lenslab.calibfiles` adds camera files, ``FILE`` or ``FILE#ID``), so the
models never import what reads other tools' files; ``import lenslab`` wires them, so every spec works
however lenslab is entered.
"""

from __future__ import annotations

from typing import Callable

#: (claims(spec) -> bool, read(spec, size) -> lens), asked in order
SOURCES: list[tuple[Callable, Callable]] = []


def add_source(claims: Callable, read: Callable) -> None:
    """Let ``read(spec, size)`` build the lens of every spec for which ``claims(spec)`` is true."""
    if (claims, read) not in SOURCES:
        SOURCES.append((claims, read))


def reader_for(spec) -> Callable | None:
    """The reader that claims ``spec``, or None for a model spec."""
    return next((read for claims, read in SOURCES if claims(spec)), None)
