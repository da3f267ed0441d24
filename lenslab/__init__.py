"""lenslab: lenses and tone curves for HDR images, and the tools to prove them right.

Heavy modules load lazily, so ``import lenslab`` and ``lenslab --help`` stay instant.
"""

from __future__ import annotations

import importlib

import lenslab.calibfiles  # noqa: F401,E402  (camera files as lens specs: it adds itself to lenslab.lens_sources)

__version__ = "0.1.0"

_LAZY = {
    "read": ("lenslab.io", "read"),
    "write": ("lenslab.io", "write"),
    "warp": ("lenslab.warp", "warp"),
    "make_lens": ("lenslab.lenses", "make_lens"),
    "Camera": ("lenslab.lenses", "Camera"),
    "tonemap": ("lenslab.tone", "tonemap"),
}


def __getattr__(name: str):
    if name in _LAZY:
        module, attr = _LAZY[name]
        return getattr(importlib.import_module(module), attr)
    raise AttributeError(f"module 'lenslab' has no attribute {name!r}")


__all__ = ["__version__", *_LAZY]
