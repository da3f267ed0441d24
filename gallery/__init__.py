"""gallery: builds an HTML page of what lenslab does, from its own renders.

``build_gallery(out_dir, *items, validate_report=None, hdri_dir=None)`` writes ``out_dir/index.html``
(see :mod:`gallery.build`); ``python -m gallery OUT`` rebuilds a page from the records stored with it.
"""

from __future__ import annotations


def build_gallery(out_dir, *items, **options):
    """See :func:`gallery.build.build_gallery` (imported on first use, so ``import gallery`` stays light)."""
    from gallery.build import build_gallery as build

    return build(out_dir, *items, **options)


__all__ = ["build_gallery"]
