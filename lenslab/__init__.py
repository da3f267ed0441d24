"""lenslab: lenses and tone curves for HDR images, and the tools to prove them right.

The front door: :func:`read` and :func:`write` image files, :class:`Camera` and :func:`make_lens`
name lenses, :func:`warp` reprojects an image from one camera into another, :func:`tonemap` takes HDR
values to a display. Heavy modules load lazily, on first use, so ``import lenslab`` and
``lenslab --help`` stay instant; ``dir(lenslab)`` lists these names all the same.

Examples
--------
>>> import lenslab
>>> sorted(set(lenslab.__all__) - {"__version__"})
['Camera', 'make_lens', 'read', 'tonemap', 'warp', 'write']
>>> {"read", "write", "warp", "Camera", "make_lens", "tonemap"} <= set(dir(lenslab))
True
"""

from __future__ import annotations

import importlib
from types import ModuleType
from typing import TYPE_CHECKING, Any

import lenslab.calibfiles  # noqa: F401,E402  (camera files as lens specs: it adds itself to lenslab.lens_sources)


def _is_exif(spec) -> bool:
    """``exif`` and ``exif:photo=PATH`` are lens specs (:mod:`lenslab.lenses.exif_view`, loaded when asked)."""
    from lenslab.lenses.spec_kinds import is_exif

    return is_exif(spec)


def _read_exif(spec, size):
    from lenslab.io.exif_orientation import stored_size  # (lenses never read files through lenslab.io)
    from lenslab.lenses.exif_view import read_exif_lens

    return read_exif_lens(spec, size, stored_size)


lenslab.calibfiles.add_source(_is_exif, _read_exif)

__version__ = "0.1.0"

if TYPE_CHECKING:  # what type checkers and editors see; at run time these load on first use
    from lenslab.io import read, write
    from lenslab.lenses import Camera, make_lens
    from lenslab.tone import tonemap
    from lenslab.warp import warp

_LAZY = {
    "read": ("lenslab.io", "read"),
    "write": ("lenslab.io", "write"),
    "warp": ("lenslab.warp", "warp"),
    "make_lens": ("lenslab.lenses", "make_lens"),
    "Camera": ("lenslab.lenses", "Camera"),
    "tonemap": ("lenslab.tone", "tonemap"),
}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        module, attr = _LAZY[name]
        return getattr(importlib.import_module(module), attr)
    raise AttributeError(f"module 'lenslab' has no attribute {name!r}")


__all__ = ["__version__", *_LAZY]


def __dir__() -> list[str]:
    """The public API (loaded lazily or not), the subpackages already imported and the dunders."""
    here = {n for n, v in globals().items()
            if n.startswith("__") or (isinstance(v, ModuleType) and v.__name__.startswith("lenslab."))}
    return sorted(here | set(__all__))
