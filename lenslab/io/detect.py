"""Format detection, kept for callers of the old names: everything now derives from the plugin
records of :mod:`lenslab.io.registry` (by magic bytes on reading, by extension on writing)."""

from __future__ import annotations

from lenslab.io.registry import format_for_path, sniff, sniff_bytes

__all__ = ["format_for_path", "sniff", "sniff_bytes"]
