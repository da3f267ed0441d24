"""The camera EXIF tags lenslab carries from a photo to the images made of it (:mod:`lenslab.io.exif`), where each
lives in an Exif block (CIPA DC-008, Exif 2.32: the first IFD or the Exif IFD), and the names OpenImageIO gives them
in an EXR's header, which ``--from exif`` reads too (:mod:`lenslab.lenses.lensfun.exif`): one table for both, that
imports nothing of lenslab.

Values are held as Python values of three kinds: ``text`` (str), ``int`` and ``ratio`` (a
:class:`fractions.Fraction`, so that a rational read from a file is written back exactly).

>>> TAGS["FocalLengthIn35mmFilm"].tag, TAGS["FocalLengthIn35mmFilm"].exr
(41989, 'Exif:FocalLengthIn35mmFilm')
>>> sorted(exr_tags({"Exif:FocalLength": 6.5, "Make": "Acme", "expTime": 0.5}).items())
[('ExposureTime', Fraction(1, 2)), ('FocalLength', Fraction(13, 2)), ('Make', 'Acme')]
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from fractions import Fraction

#: the longest text value carried (a maker's or a lens's name); a longer one is not a camera's
TEXT_MAX = 255
#: a number given as text (an EXR attribute of type string under a number's name): a decimal, its exponent of at
#: most 3 digits, or a fraction of integers; at most 64 characters. Read exactly (6.81 is 681/100), and only where a
#: double holds it: an exponent of 10**9 digits would build an integer of that many digits from a few bytes
TEXT_NUMBER = re.compile(r"[ \t]*[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]{1,3})?[ \t]*"
                         r"|[ \t]*[+-]?[0-9]+/[0-9]+[ \t]*")  # (ASCII: \s and \d take characters float() does not)


@dataclass(frozen=True)
class Tag:
    """One carried tag: its IFD (0: the first, ``exif``: the Exif IFD), number, kind (``text``, ``int``, ``ratio``),
    its TIFF type when written (2 ASCII, 3 SHORT, 4 LONG, 5 RATIONAL) and its EXR attribute (OpenImageIO's name)."""

    ifd: str
    tag: int
    kind: str
    type: int
    exr: str


def _t(ifd, tag, kind, exr, type_=None) -> Tag:
    return Tag(ifd, tag, kind, type_ or {"text": 2, "int": 3, "ratio": 5}[kind], exr)


#: the carried tags by their Exif names (the EXR names are those OpenImageIO reads and writes: ExposureTime and
#: FNumber as OpenEXR's standard expTime and aperture, Make, Model and Orientation bare, the rest Exif:NAME)
TAGS = {
    "Make": _t("0", 0x010F, "text", "Make"),
    "Model": _t("0", 0x0110, "text", "Model"),
    "Orientation": _t("0", 0x0112, "int", "Orientation"),
    "ExposureTime": _t("exif", 0x829A, "ratio", "expTime"),
    "FNumber": _t("exif", 0x829D, "ratio", "aperture"),
    "PhotographicSensitivity": _t("exif", 0x8827, "int", "Exif:PhotographicSensitivity"),
    "DateTimeOriginal": _t("exif", 0x9003, "text", "Exif:DateTimeOriginal"),
    "OffsetTimeOriginal": _t("exif", 0x9011, "text", "Exif:OffsetTimeOriginal"),
    "SubjectDistance": _t("exif", 0x9206, "ratio", "Exif:SubjectDistance"),
    "FocalLength": _t("exif", 0x920A, "ratio", "Exif:FocalLength"),
    "PixelXDimension": _t("exif", 0xA002, "int", "Exif:PixelXDimension", 4),
    "PixelYDimension": _t("exif", 0xA003, "int", "Exif:PixelYDimension", 4),
    "FocalPlaneXResolution": _t("exif", 0xA20E, "ratio", "Exif:FocalPlaneXResolution"),
    "FocalPlaneYResolution": _t("exif", 0xA20F, "ratio", "Exif:FocalPlaneYResolution"),
    "FocalPlaneResolutionUnit": _t("exif", 0xA210, "int", "Exif:FocalPlaneResolutionUnit"),
    "FocalLengthIn35mmFilm": _t("exif", 0xA405, "int", "Exif:FocalLengthIn35mmFilm"),
    "LensMake": _t("exif", 0xA433, "text", "Exif:LensMake"),
    "LensModel": _t("exif", 0xA434, "text", "Exif:LensModel"),
}
#: (IFD, number) -> name
BY_NUMBER = {(t.ifd, t.tag): name for name, t in TAGS.items()}
#: the first IFD's pointer to the Exif IFD; the Exif IFD's version (written 0232: Exif 2.32)
EXIF_POINTER, EXIF_VERSION = 0x8769, 0x9000
#: OpenEXR's standard attributes read where OpenImageIO's names are absent (files of other writers)
EXR_FALLBACK = {"Make": "cameraMake", "Model": "cameraModel", "LensMake": "lensMake", "LensModel": "lensModel",
                "FocalLength": "nominalFocalLength", "SubjectDistance": "focus",
                "PhotographicSensitivity": "isoSpeed"}


def checked(name: str, value):
    """``value`` as tag ``name``'s kind holds it, or None where it is not one (a text over :data:`TEXT_MAX`
    characters, a negative or non-finite number, an integer beyond its type)."""
    kind = TAGS[name].kind
    if kind == "text":
        text = value.decode("utf-8", "replace") if isinstance(value, bytes) else value
        if not isinstance(text, str):
            return None
        text = text.split("\0", 1)[0].strip()
        return text if 0 < len(text) <= TEXT_MAX else None
    if isinstance(value, str) and not _double_text(value):
        return None
    try:
        number = Fraction(value) if not isinstance(value, Fraction) else value
    except (TypeError, ValueError, OverflowError, ZeroDivisionError):  # NaN, infinity, text
        return None
    if number < 0:
        return None
    if kind == "int":
        limit = 0xFFFFFFFF if TAGS[name].type == 4 else 0xFFFF
        return int(number) if number.denominator == 1 and number <= limit else None
    return number


def _double_text(text: str) -> bool:
    """Whether ``text`` is a number :data:`TEXT_NUMBER` reads whose value a double holds, finite and not lost to
    zero (``1e-999`` is no camera's value)."""
    import math

    if len(text) > 64 or not TEXT_NUMBER.fullmatch(text):
        return False
    num, _, den = text.partition("/")
    value = float(num) / float(den) if den and float(den) else float(num)
    return bool(den == "" or float(den)) and math.isfinite(value) and (value != 0 or not re.search(r"[1-9]", num))


def _plain(value, ratio: bool = False):
    """An EXR attribute's value as a number or text (OpenEXR's bindings give a double as a 1-element array, a float as
    a Python float). ``ratio``: a float is the rational it stands for (:func:`single_ratio`)."""
    import numpy as np

    if isinstance(value, np.ndarray):
        return value.reshape(-1)[0].item() if value.size == 1 else None
    value = value.item() if isinstance(value, np.generic) else value
    return single_ratio(value) if ratio and isinstance(value, float) else value


def _simplest(lo: Fraction, hi: Fraction) -> Fraction:
    """The fraction of smallest denominator in ``[lo, hi]`` (0 <= lo <= hi): continued fractions."""
    whole = lo.numerator // lo.denominator
    if whole == lo or whole + 1 <= hi:
        return Fraction(whole if whole == lo else whole + 1)
    return whole + 1 / _simplest(1 / (hi - whole), 1 / (lo - whole))


def single_ratio(value: float):
    """A 32-bit float (OpenImageIO writes an EXR's rationals so, and OpenEXR's ``expTime`` and ``aperture`` are
    floats) as the simplest fraction that rounds to it: 6.81 stored as 6.8099999428 is 681/100, as the photo had it.
    A value no float32 holds exactly (a double's) is returned as it is.

    >>> import numpy as np
    >>> single_ratio(float(np.float32(6.81))), single_ratio(float(np.float32(1 / 250))), single_ratio(0.1)
    (Fraction(681, 100), Fraction(1, 250), 0.1)
    """
    import numpy as np

    single = np.float32(value)
    if not (np.isfinite(single) and single > 0 and float(single) == value):
        return value
    below, above = (Fraction(float(np.nextafter(single, np.float32(t)))) for t in (0.0, np.inf))
    exact = Fraction(value)
    found = _simplest((below + exact) / 2, (exact + above) / 2)
    return found if np.float32(found.numerator / found.denominator) == single else exact


def exr_tags(header: dict) -> dict:
    """The carried tags an EXR header holds under OpenImageIO's names (or OpenEXR's standard ones), checked."""
    out = {}
    for name, tag in TAGS.items():
        value = header.get(tag.exr, header.get(EXR_FALLBACK.get(name, "")))
        value = checked(name, _plain(value, tag.kind == "ratio")) if value is not None else None
        if value is not None:
            out[name] = value
    return out


def exr_attributes(tags: dict) -> dict:
    """Tags as EXR header attributes under OpenImageIO's names: text as strings, integers as ints, rationals as 32-bit
    floats, the type OpenImageIO writes and the only one its JPEG writer carries on, where the float gives the
    rational back (:func:`single_ratio`: 681/100, 1/250), else as doubles (a float would move a field of view by
    1e-6 degree).

    >>> from fractions import Fraction as F
    >>> {k: type(v).__name__ for k, v in exr_attributes({"FocalLength": F(681, 100), "FNumber": F(1000001, 300000),
    ...                                                  "Make": "Acme", "FocalLengthIn35mmFilm": 24}).items()}
    {'Exif:FocalLength': 'float', 'aperture': 'ndarray', 'Make': 'str', 'Exif:FocalLengthIn35mmFilm': 'int'}
    """
    import numpy as np

    out = {}
    for name, value in tags.items():
        kind = TAGS[name].kind
        if kind == "ratio":
            single = float(np.float32(value))
            out[TAGS[name].exr] = single if single_ratio(single) == value else np.array([float(value)], np.float64)
        else:
            out[TAGS[name].exr] = int(value) if kind == "int" else str(value)
    return out
