"""What a gallery shows: small records that point at HDR files and carry the numbers measured with them.

A gallery is rebuilt from these records alone (they are saved as ``gallery.json`` next to
``index.html``), so every image they name is a file path relative to the gallery directory.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Any

from gallery.errors import GalleryError


@dataclass
class Display:
    """How HDR images become display images on the page: one curve and one exposure for all of them,
    so that a warped view and its direct trace are shown exactly alike."""

    curve: str = "hable"
    exposure: float = 0.0
    kind: str = "display"


@dataclass
class Panorama:
    """The HDR panorama every view is warped from."""

    path: str
    spec: str
    size: tuple[int, int]
    scene: str = ""
    spp: int = 0
    seconds: float = 0.0
    eye: tuple[float, float, float] | None = None
    integrator: str = ""
    max_depth: int = 0
    kind: str = "panorama"


@dataclass
class LensView:
    """One view warped from the panorama, optionally with a direct trace of the same camera."""

    name: str
    spec: str
    size: tuple[int, int]
    warped: str
    warp_seconds: float = 0.0
    pose: dict[str, float] = field(default_factory=dict)
    settings: dict[str, Any] = field(default_factory=dict)
    note: str = ""
    direct: str | None = None
    trace_seconds: float | None = None
    trace_spp: int | None = None
    error: dict[str, float] | None = None
    kind: str = "lens"


@dataclass
class ToneSet:
    """One HDR image shown under several tone curves."""

    source: str
    curves: list[str]
    exposure: float = 0.0
    label: str = ""
    kind: str = "tone"


@dataclass
class FileList:
    """Files a run wrote, for the page to list and link."""

    files: list[dict[str, str]]
    kind: str = "files"


@dataclass
class RunInfo:
    """How the page was made: the command, the settings and the total time."""

    command: str = ""
    seconds: float = 0.0
    settings: dict[str, Any] = field(default_factory=dict)
    kind: str = "run"


KINDS = {cls.__dataclass_fields__["kind"].default: cls for cls in (Display, Panorama, LensView, ToneSet, FileList, RunInfo)}


def to_json(item) -> dict[str, Any]:
    """A JSON-ready dict of one record (tuples become lists)."""
    return dataclasses.asdict(item)


def from_json(data: dict[str, Any]):
    """The record a :func:`to_json` dict came from; unknown keys are ignored (files from newer versions)."""
    try:
        cls = KINDS[data["kind"]]
    except KeyError:
        raise GalleryError(
            f"gallery record of unknown kind {data.get('kind')!r}; known kinds: {', '.join(KINDS)}"
        ) from None
    names = {f.name for f in dataclasses.fields(cls)}
    values = {k: v for k, v in data.items() if k in names}
    for key in ("size", "eye"):
        if isinstance(values.get(key), list):
            values[key] = tuple(values[key])
    return cls(**values)
