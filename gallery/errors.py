"""The gallery's error type."""

from __future__ import annotations

from lenslab.errors import LenslabError


class GalleryError(LenslabError, ValueError):
    """A gallery cannot be built as asked (missing or unreadable record file, image or report)."""
