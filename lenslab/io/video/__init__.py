"""Video clips: decoding to linear light and encoding from it (:mod:`lenslab.io.video.clips`), the colour
rules (:mod:`~lenslab.io.video.colour`, :mod:`~lenslab.io.video.ycbcr`), the codecs
(:mod:`~lenslab.io.video.codecs`), the container's box walk (:mod:`~lenslab.io.video.layout`) and the
decoder's prefetch thread (:mod:`~lenslab.io.video.prefetch`).

``lenslab.io.video.NAME`` is ``lenslab.io.video.clips.NAME``, loaded on first use: a command that only
needs the codec table (``lenslab warp --help``, a still image's warp) does not load NumPy or PyAV for it.
"""

from __future__ import annotations


def __getattr__(name: str):
    if name.startswith("__") or name == "clips":
        raise AttributeError(name)
    import importlib

    return getattr(importlib.import_module("lenslab.io.video.clips"), name)
