"""The input file a command is working on, for notes that count files rather than the images made from them
(compare-tones' panels, a clip's frames, a batch's files on threads): a context variable, so each thread of a
batch has its own. Kept apart from the packages that read it, so setting it costs no import."""

from __future__ import annotations

import contextlib
import contextvars
from typing import Iterator

CURRENT: contextvars.ContextVar[str | None] = contextvars.ContextVar("lenslab_input", default=None)
#: whether the images made now were resampled (a warp): their negatives beyond a codec's are a filter's lobes
RESAMPLED: contextvars.ContextVar[bool] = contextvars.ContextVar("lenslab_resampled", default=False)


@contextlib.contextmanager
def from_input(path=None, resampled: bool | None = None) -> Iterator[None]:
    """Within the block, the images made come from the input ``path`` (None: as around the block) and were
    resampled or not (None: as around the block)."""
    tokens = []
    if path is not None:
        tokens.append((CURRENT, CURRENT.set(str(path))))
    if resampled is not None:
        tokens.append((RESAMPLED, RESAMPLED.set(bool(resampled))))
    try:
        yield
    finally:
        for var, token in reversed(tokens):
            var.reset(token)


__all__ = ["CURRENT", "RESAMPLED", "from_input"]
