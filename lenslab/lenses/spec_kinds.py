"""Lens specs whose lens is read from a file's metadata, told apart from the others without loading their readers:
``exif`` / ``exif:photo=PATH`` (:mod:`lenslab.lenses.exif_view`) and ``auto`` / ``lensfun:auto``
(:mod:`lenslab.lenses.lensfun.exif`). A command that checks ``--from`` / ``--to`` asks these first, so a spec that
names a model (``fisheye:fov=180``) loads neither reader."""

from __future__ import annotations

import re

from lenslab.errors import LensError

#: ``exif`` and ``exif:...`` (group 1: the ``:...`` part)
EXIF_SPEC = re.compile(r"\s*exif\s*(:.*)?", re.S | re.I)
_AUTO_SPEC = re.compile(r"\s*(lensfun:)?auto\s*(,.*)?", re.S | re.I)


def is_exif(spec) -> bool:
    """``exif`` (the photo a command reads) or ``exif:photo=PATH``."""
    return isinstance(spec, str) and EXIF_SPEC.fullmatch(spec) is not None


def exif_photo(spec: str) -> str | None:
    """The ``photo=`` of an ``exif:`` spec, or None for plain ``exif``."""
    rest = EXIF_SPEC.fullmatch(spec).group(1)
    if not rest or not rest[1:].strip():
        return None
    from lenslab.lenses.registry import split_items

    values = {}
    for item in split_items(rest[1:], spec):
        key, eq, value = item.partition("=")
        if key.strip() != "photo" or not eq or not value.strip():
            raise LensError(f"lens spec {spec!r}: exif takes photo=PATH alone (the photo whose EXIF gives the lens)")
        values["photo"] = value.strip()
    return values["photo"]


def is_auto(spec) -> bool:
    """``lensfun:auto`` or ``auto`` (with or without more values after a comma)."""
    return isinstance(spec, str) and _AUTO_SPEC.fullmatch(spec) is not None


__all__ = ["EXIF_SPEC", "exif_photo", "is_auto", "is_exif"]
