"""The camera and lens a photo names in its metadata, for ``lensfun:auto`` and ``--from auto``.

:func:`photo_lens` reads the camera maker and model, the lens maker and model, focal length,
f-number and focus distance of a file: EXIF through exifread (JPEG, TIFF and DNG-derived TIFF, PNG's
eXIf chunk, WebP, HEIC), XMP packets (``aux:Lens``, ``exifEX:LensModel``...) where EXIF lacks a field,
and for EXR the attributes OpenImageIO writes (``Make``, ``Model``, ``Exif:FocalLength``,
``Exif:FocalLengthIn35mmFilm``, ``Exif:FocalPlaneXResolution``..., as ``lenslab convert`` writes them too), else
OpenEXR's standard ones (``cameraMake``, ``lensModel``, ``nominalFocalLength``, ``aperture``, ``focus``). Only
headers are read: at most :data:`XMP_SCAN` bytes of the file for XMP.
:func:`lenslab.lenses.lensfun.match.auto_spec` turns them into the explicit ``lensfun:`` spec, so
``lensfun:auto`` is exactly that spec.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

from lenslab.errors import LensError
from lenslab.lenses.spec_kinds import is_auto  # noqa: F401 (this module's name too)

#: bytes of a file searched for an XMP packet (JPEG puts it in the first 64 KiB; TIFF near the start)
XMP_SCAN = 4 << 20
EXR_MAGIC = b"\x76\x2f\x31\x01"


@dataclass
class PhotoLens:
    """What a file says about its camera and lens (None: not recorded)."""

    path: str
    camera_maker: str | None = None
    camera_model: str | None = None
    lens_maker: str | None = None
    lens_model: str | None = None
    focal: float | None = None  # mm
    aperture: float | None = None  # f-number
    distance: float | None = None  # m
    focal35: float | None = None  # 35 mm equivalent focal length, mm
    plane_x: float | None = None  # FocalPlaneXResolution: pixels per plane_unit across the stored width
    plane_y: float | None = None  # FocalPlaneYResolution
    plane_unit: float | None = None  # FocalPlaneResolutionUnit: 1 none, 2 inch, 3 cm (4 mm, 5 um: exiftool's)
    exif_width: float | None = None  # PixelXDimension (ExifImageWidth): the stored frame the plane refers to
    exif_height: float | None = None  # PixelYDimension
    sources: list[str] = field(default_factory=list)  # where the values came from
    #: numbers the file records that are no value (0, negative, 0/0: FocalLengthIn35mmFilm 0 is Exif's "unknown"), as
    #: the file writes them, by field: their field stays None, and an error can say what the file holds
    held: dict[str, str] = field(default_factory=dict)

    @property
    def camera(self) -> str | None:
        """Maker and model once: EXIF's model often repeats the maker ("Canon", "Canon EOS 600D")."""
        return camera_name(self.camera_maker, self.camera_model)

    @property
    def crop(self) -> float | None:
        """The sensor's crop factor from the 35 mm equivalent focal length, where both are recorded."""
        if self.focal and self.focal35:
            return self.focal35 / self.focal
        return None

    def describe(self) -> str:
        parts = [self.camera or "camera not recorded", self.lens_model or "lens not recorded"]
        if self.focal:
            parts.append(f"{self.focal:g} mm")
        if self.aperture:
            parts.append(f"f/{self.aperture:g}")
        if self.distance:
            parts.append(f"focused at {self.distance:g} m")
        return ", ".join(parts) + (f" ({', '.join(self.sources)})" if self.sources else "")


def camera_name(maker: str | None, model: str | None) -> str | None:
    maker, model = (maker or "").strip(), (model or "").strip()
    if not model:
        return maker or None
    first = maker.split()[0].lower() if maker else ""
    if not maker or model.lower().startswith(first):
        return model
    return f"{maker} {model}"


def _number(value) -> float | None:
    """A float from an EXIF rational/number/text ("24/1", Ratio, [Ratio]); None when not a positive number."""
    while isinstance(value, (list, tuple)):  # exifread: a list of values (each may be a tuple)
        value = value[0] if value else None
    if value is None:
        return None
    try:
        if isinstance(value, str):
            a, slash, b = value.strip().partition("/")
            v = float(a) / float(b) if slash else float(a)
        else:
            v = float(value)
    except (TypeError, ValueError, ZeroDivisionError):
        return None
    return v if v > 0 and v == v and v != float("inf") else None


def _shown(value) -> str | None:
    """A recorded number as the file writes it ("0", "-5", "0/0"), for one that :func:`_number` finds no value; None
    when nothing (or no number) is recorded."""
    while isinstance(value, (list, tuple)):
        value = value[0] if value else None
    num, den = getattr(value, "numerator", None), getattr(value, "denominator", None)
    if isinstance(num, int) and isinstance(den, int) and den == 0:
        return f"{num}/0"
    try:
        if isinstance(value, str):  # XMP: "24", "0/1", "0/0"
            a, slash, b = value.strip().partition("/")
            num, den = float(a), float(b) if slash else 1.0
            return value.strip() if den == 0 else f"{num / den:g}"
        return f"{float(value):g}"
    except (TypeError, ValueError, ZeroDivisionError):
        return None


def _numbers(info: PhotoLens, raw: dict) -> dict:
    """``raw`` (field -> recorded value) as numbers (:func:`_number`); a recorded one that is no value is kept in
    ``info.held`` as written (the first source's)."""
    got = {}
    for name, value in raw.items():
        got[name] = _number(value)
        shown = _shown(value) if got[name] is None else None
        if shown is not None:
            info.held.setdefault(name, shown)
    return got


def _text(value) -> str | None:
    if value is None:
        return None
    text = str(value.values if hasattr(value, "values") and isinstance(value.values, str) else value)
    text = text.replace("\x00", "").strip()
    return text or None


def _exif(path: Path, info: PhotoLens) -> None:
    import logging

    import exifread

    log = logging.getLogger("exifread")
    level = log.level
    log.setLevel(logging.CRITICAL + 1)  # a damaged header is "nothing recorded", not warnings on stderr
    tags = {}
    try:
        for find in (_file_exif, _heif_exif):  # a HEIF whose Exif item exifread cannot find: libheif finds it
            try:
                tags = find(path, exifread)
            except Exception:  # exifread raises its own errors for damaged headers: nothing recorded
                tags = {}
            if tags:
                break
    finally:
        log.setLevel(level)
    if not tags:
        return
    got = {
        "camera_maker": _text(tags.get("Image Make")),
        "camera_model": _text(tags.get("Image Model")),
        "lens_maker": _text(tags.get("EXIF LensMake")),
        "lens_model": _text(tags.get("EXIF LensModel")),
        **_numbers(info, {name: getattr(tags.get(f"EXIF {tag}"), "values", None)
                          for name, tag in {**NUMBER_TAGS, **PLANE_TAGS}.items()}),
    }
    _fill(info, got, "EXIF")


def _file_exif(path: Path, exifread) -> dict:
    with open(path, "rb") as f:
        return exifread.process_file(f, details=False)


def _heif_exif(path: Path, exifread) -> dict:
    """The EXIF tags of a HEIF's primary image as libheif (pillow-heif) finds them; {} for any other file."""
    import io

    with open(path, "rb") as f:
        if f.read(8)[4:] != b"ftyp":
            return {}
    try:
        import pillow_heif
    except ImportError:  # (reading the image says how to install it)
        return {}
    data = pillow_heif.open_heif(str(path)).info.get("exif") or b""
    return exifread.process_file(io.BytesIO(data[6:] if data.startswith(b"Exif\0\0") else data), details=False)


#: PhotoLens field -> the EXIF tag (exifread's name) of the lens's numbers
NUMBER_TAGS = {"focal": "FocalLength", "aperture": "FNumber", "distance": "SubjectDistance",
               "focal35": "FocalLengthIn35mmFilm"}
#: PhotoLens field -> the EXIF tag (exifread's name, XMP's exif: property) of the focal plane and frame
PLANE_TAGS = {"plane_x": "FocalPlaneXResolution", "plane_y": "FocalPlaneYResolution",
              "plane_unit": "FocalPlaneResolutionUnit", "exif_width": "ExifImageWidth",
              "exif_height": "ExifImageLength"}


#: PhotoLens field -> the Exif tag it holds (lenslab.exif_tags.TAGS), as an EXR's header names them
FIELD_TAGS = {"camera_maker": "Make", "camera_model": "Model", "lens_maker": "LensMake", "lens_model": "LensModel",
              "focal": "FocalLength", "aperture": "FNumber", "distance": "SubjectDistance",
              "focal35": "FocalLengthIn35mmFilm", "plane_x": "FocalPlaneXResolution",
              "plane_y": "FocalPlaneYResolution", "plane_unit": "FocalPlaneResolutionUnit",
              "exif_width": "PixelXDimension", "exif_height": "PixelYDimension"}


#: XMP property -> PhotoLens field (attribute or element form)
XMP_KEYS = {
    "tiff:Make": "camera_maker", "tiff:Model": "camera_model", "exifEX:LensMake": "lens_maker",
    "exifEX:LensModel": "lens_model", "aux:Lens": "lens_model", "exif:FocalLength": "focal",
    "exif:FNumber": "aperture", "exif:SubjectDistance": "distance", "exif:FocalLengthIn35mmFilm": "focal35",
    "exif:FocalPlaneXResolution": "plane_x", "exif:FocalPlaneYResolution": "plane_y",
    "exif:FocalPlaneResolutionUnit": "plane_unit", "exif:PixelXDimension": "exif_width",
    "exif:PixelYDimension": "exif_height",
}
#: the fields that hold numbers
NUMBERS = ("focal", "aperture", "distance", "focal35", "plane_x", "plane_y", "plane_unit", "exif_width", "exif_height")


def _xmp(path: Path, info: PhotoLens) -> None:
    with open(path, "rb") as f:
        data = f.read(XMP_SCAN)
    start = data.find(b"<x:xmpmeta")
    if start < 0:
        return
    end = data.find(b"</x:xmpmeta>", start)
    packet = data[start:end if end > 0 else len(data)].decode("utf-8", "replace")
    got = {}
    for key, name in XMP_KEYS.items():
        k = re.escape(key)
        m = (re.search(rf'{k}\s*=\s*"([^"]*)"', packet)
             or re.search(rf"<{k}>\s*(?:<rdf:Alt>\s*<rdf:li[^>]*>)?([^<]*)<", packet))
        if m and name not in got:
            value = m.group(1).strip()
            got[name] = _numbers(info, {name: value})[name] if name in NUMBERS else (value or None)
    _fill(info, got, "XMP")


def _exr(path: Path, info: PhotoLens) -> None:
    import OpenEXR

    from lenslab.library_output import quiet_library

    try:
        with quiet_library():
            header = OpenEXR.File(str(path), header_only=True).parts[0].header
    except Exception:
        raise LensError(f"{path}: OpenEXR cannot read the header; the file is damaged") from None
    from lenslab.exif_tags import exr_tags

    tags = exr_tags(header)  # OpenImageIO's names (Make, Exif:FocalLength...), else OpenEXR's (cameraMake...)
    got = {field: _text(tags[tag]) if tag in tags else None for field, tag in FIELD_TAGS.items() if field not in NUMBERS}
    got.update(_numbers(info, {field: tags.get(tag) for field, tag in FIELD_TAGS.items() if field in NUMBERS}))
    _fill(info, got, "EXR attributes")


def _fill(info: PhotoLens, got: dict, source: str) -> None:
    used = False
    for name, value in got.items():
        if value is not None and getattr(info, name) is None:
            setattr(info, name, value)
            used = True
    if used:
        info.sources.append(source)


def photo_lens(path) -> PhotoLens:
    """The camera and lens ``path``'s metadata records (fields not recorded stay None)."""
    path = Path(path)
    if not path.is_file():  # a missing input, as a missing image is (exit 1), not a mistyped spec
        import errno
        import os

        code = errno.EISDIR if path.is_dir() else errno.ENOENT
        raise (IsADirectoryError if path.is_dir() else FileNotFoundError)(code, os.strerror(code), str(path))
    info = PhotoLens(str(path))
    with open(path, "rb") as f:
        magic = f.read(4)
    if magic == EXR_MAGIC:
        _exr(path, info)
    else:
        _exif(path, info)
    _xmp(path, info)
    return info
