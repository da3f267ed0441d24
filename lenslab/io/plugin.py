"""What a file format plugin declares: one :class:`Format` record per format, in the manner of imageio v3.

A plugin is one module under :mod:`lenslab.io.formats` holding a module-level ``FORMATS`` tuple of
records. Each record says what the format is called, the extensions it is written with, how to
recognise its first bytes, what it holds (linear HDR floats or display-encoded codes, alpha,
channel counts, bit depths, sample types), which read and write options it takes, the two
functions that read and write it and the probe that describes a file's structure. Detection
(:mod:`lenslab.io.registry`), ``lenslab.read`` / ``lenslab.write``, ``lenslab info`` (its probes and
``--formats``) and the command-line format choices all derive from these records, so adding a format
is adding one module.

The read and write functions import their codec lazily: the registry loads every plugin at once and
must stay quick to import (commands start without importing OpenEXR, OpenCV or tifffile).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable


@dataclass(frozen=True)
class Format:
    """One file format.

    ``read(path, selector, **read_options) -> (float32 H x W x C image, meta)`` receives only the
    options named in ``read_options``, and ``parsed=`` when the ``declare`` hook's answer carries what it
    parsed of the header (:attr:`lenslab.io.budget.Declared.parsed`); ``write(tmp_path, image, **write_options)`` writes a float32
    image whose channel count is one of ``channels`` (the caller has already fitted it).
    """

    name: str
    title: str
    extensions: tuple[str, ...]
    #: True if ``head`` (the first 32 bytes of a file) starts a file of this format
    magic: Callable[[bytes], bool]
    #: holds linear floats (written without a tone curve); False: display-encoded codes
    hdr: bool
    alpha: bool
    #: channel counts a written file may hold (before alpha is dropped for formats without it)
    channels: tuple[int, ...]
    bit_depths: tuple[int, ...]
    sample_types: tuple[str, ...]
    read: Callable | None = None
    write: Callable | None = None
    read_options: tuple[str, ...] = ()
    #: write option name -> one line of help
    write_options: dict[str, str] = field(default_factory=dict)
    #: accepts ``file:selector`` (parts and layers)
    selectors: bool = False
    #: can store a lenslab camera
    camera: bool = False
    #: the names the ``compression`` write option takes (checked once, before a batch starts)
    compressions: tuple[str, ...] = ()
    #: one line for ``lenslab info --formats`` and the docs
    note: str = ""
    #: "image", or "video" (many frames: ``read`` gives the first, :mod:`lenslab.io.video` the rest)
    kind: str = "image"
    #: ``declare(path, **read_options) -> lenslab.io.budget.Declared``: what the header declares and the
    #: fewest bytes it needs, read before any pixel is decoded (:func:`lenslab.io.budget.admit`)
    declare: Callable | None = None
    #: sample types whose files hold straight (unassociated) colour with alpha; the others hold it
    #: premultiplied (memory's convention; the plugin converts at the boundary, :mod:`lenslab.io.alpha`)
    straight_alpha: tuple[str, ...] = ()
    #: ``probe(path) -> dict`` (JSON-ready): what the file holds beyond the pixels ``read`` returns (EXR parts
    #: and channels, TIFF pages, the Radiance header, video streams), for ``lenslab info``; :func:`header_only`
    #: for formats whose one image and header ``read`` already reports in full
    probe: Callable | None = None
    #: ``channel_names(path) -> list[str]``: the names of the channels ``read`` gives with no selector, from
    #: the header alone (no pixel decoded), for formats whose files name their channels
    channel_names: Callable | None = None
    #: a float format whose files cannot hold a negative sample (Radiance RGBE: unsigned mantissas), written
    #: as 0: a wide-gamut image's colours outside sRGB are clipped for it as for a display format
    clips_negatives: bool = False
    #: the sample types a written file holds, as ``--pixel-type`` names them, where :attr:`pixel_types` cannot pair
    #: them from ``bit_depths`` and ``sample_types`` (EXR: half and float; its 32-bit uint is read, and kept per channel)
    written_types: tuple[str, ...] = ()

    @property
    def pixel_types(self) -> tuple[str, ...]:
        """The sample types a written file of this format holds, as ``--pixel-type`` names them: ``uint8`` and
        ``uint16`` for integers of those depths, ``half``, ``float`` (32-bit), or the format's own (``rgbe``);
        :attr:`written_types` where given."""
        if self.written_types:
            return self.written_types
        ints = tuple(f"uint{b}" for b in self.bit_depths if "uint" in self.sample_types and b <= 16)
        return ints + tuple(t for t in self.sample_types if t != "uint")

    def holds_straight(self, sample_type: str = "uint") -> bool:
        """Whether a file of this format, written with ``sample_type`` samples, holds straight colour."""
        return self.alpha and sample_type in self.straight_alpha

    @property
    def readable(self) -> bool:
        return self.read is not None

    @property
    def writable(self) -> bool:
        return self.write is not None

    def describe(self) -> dict:
        """The record as plain JSON-ready data."""
        return {"name": self.name, "title": self.title, "extensions": list(self.extensions), "hdr": self.hdr,
                "alpha": self.alpha, "channels": list(self.channels), "bit_depths": list(self.bit_depths),
                "sample_types": list(self.sample_types), "read": self.readable, "write": self.writable,
                "write_options": dict(self.write_options), "selectors": self.selectors, "camera": self.camera,
                "compressions": list(self.compressions),
                "pixel_types": list(self.pixel_types) if self.writable and self.kind == "image" else [],
                "note": self.note, "kind": self.kind, "straight_alpha": list(self.straight_alpha)}


def header_only(path) -> dict:
    """The probe of a format whose file is one image and a header that ``read`` reports in full (its size,
    channels, depth and attributes): nothing more to describe, so ``lenslab info`` shows the reader's
    attributes."""
    return {}


def _call(module: str, name: str, *args, **kwargs):
    """``module.name(*args, **kwargs)``, the module imported at the call."""
    from importlib import import_module

    return getattr(import_module(module), name)(*args, **kwargs)


def ldr_hooks(kind: str) -> tuple:
    """``(read, write, declare)`` of the ``"jpg"`` or ``"png"`` plugin: :mod:`lenslab.io.ldr_layout`'s, imported at
    the first call, so that loading the registry loads no codec (a video warp reads no image); they pickle."""
    from functools import partial

    module = "lenslab.io.ldr_layout"
    return (partial(_call, module, "_read", kind=kind), partial(_call, module, "_write", kind=kind),
            partial(_call, module, f"declare_{kind}"))
