"""A photo's own lens from its EXIF: ``--from exif``, the pinhole (``perspective``) view of its 35 mm equivalent
focal length, for the image as shown (after its EXIF orientation).

The convention (``docs/conventions.md``, "35 mm equivalent focal length"): Exif 2.3's (CIPA DC-008)
``FocalLengthIn35mmFilm`` is the focal length a 36 x 24 mm frame needs for the photo's angle of view, matched
across the diagonal, ``D = hypot(36, 24) = 43.27 mm``. So, for a photo of ``W x H`` square pixels as shown::

    tan(dfov / 2) = D / (2 f35)                          the diagonal field of view
    tan(fov / 2)  = tan(dfov / 2) W / hypot(W, H)         across the width: perspective's fov

Without ``FocalLengthIn35mmFilm``, ``f35 = FocalLength D / d`` with ``d`` the sensor's diagonal in mm: the
recorded frame (``PixelXDimension`` x ``PixelYDimension``, else the photo's stored pixels) over
``FocalPlaneXResolution`` and ``FocalPlaneYResolution`` (pixels per ``FocalPlaneResolutionUnit``; Y as X when not
recorded). A photo without
either refuses in one line naming the tags it lacks; so does one whose sensor would be under 1 mm or over 100 mm
across (:data:`SENSOR_DIAGONAL`, as exiftool) or whose equivalent is beyond Exif's 1 to 65535 mm.

>>> round(horizontal_fov(24.0, 3000, 2000), 2), round(diagonal_fov(24.0), 2)
(73.74, 84.06)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from lenslab.errors import LensError
from lenslab.lenses.spec_kinds import exif_photo, is_exif  # noqa: F401 (this module's names too)

#: the diagonal of the 36 x 24 mm frame that the 35 mm equivalent focal length is matched to, mm
FRAME_DIAGONAL = math.hypot(36.0, 24.0)
#: FocalPlaneResolutionUnit -> mm: 2 inch, 3 cm (Exif 2.3); 4 mm and 5 um as exiftool reads them. 1 (no unit) has none
UNIT_MM = {2: 25.4, 3: 10.0, 4: 1.0, 5: 0.001}
#: the 35 mm equivalents read, mm: Exif's FocalLengthIn35mmFilm is a SHORT (0 unknown); beyond, an XMP value or a
#: focal plane's gives no pinhole (a field of 180 or 0 degrees)
FOCAL35_RANGE = (1.0, 65535.0)
#: the sensor diagonals read from a focal plane, mm (exiftool's CalcScaleFactor35efl keeps 1 to 100 mm): outside,
#: the frame is not the sensor's (a copy made smaller without PixelXDimension has its own pixels taken for it)
SENSOR_DIAGONAL = (1.0, 100.0)


def diagonal_fov(focal35: float) -> float:
    """The diagonal field of view, degrees, of a 35 mm equivalent focal length (float64)."""
    return math.degrees(2.0 * math.atan(FRAME_DIAGONAL / (2.0 * focal35)))


def horizontal_fov(focal35: float, width: float, height: float) -> float:
    """The field of view across the width, degrees, of a ``width x height`` image (square pixels) of the 35 mm
    equivalent focal length ``focal35``: its diagonal field shared out by the image's own aspect."""
    return math.degrees(2.0 * math.atan(FRAME_DIAGONAL / (2.0 * focal35) * width / math.hypot(width, height)))


@dataclass(frozen=True)
class ExifView:
    """The pinhole view a photo's EXIF gives: the 35 mm equivalent focal length, where it came from, and the
    fields of view of the image as shown (``size``, W x H)."""

    focal35: float
    source: str
    size: tuple[int, int]

    @property
    def fov(self) -> float:
        return horizontal_fov(self.focal35, *self.size)

    @property
    def dfov(self) -> float:
        return diagonal_fov(self.focal35)

    @property
    def spec(self) -> str:
        """``perspective:fov=...``: its fov to 12 significant digits (1e-9 degree)."""
        return f"perspective:fov={self.fov:.12g}"

    def describe(self) -> str:
        return (f"{self.spec} (35 mm equivalent {self.focal35:.4g} mm, from {self.source}: {self.dfov:.1f} degrees "
                f"across the diagonal, {self.fov:.1f} across the {self.size[0]}x{self.size[1]} image as shown)")


def equivalent_focal(info, size: tuple[int, int]) -> tuple[float, str]:
    """The 35 mm equivalent focal length of the photo described by ``info`` (a
    :class:`~lenslab.lenses.lensfun.exif.PhotoLens`) whose image as stored (before its EXIF orientation: the frame
    FocalPlaneXResolution counts across) is ``size``, and the tags it came from; a :class:`LensError` naming the
    missing tags when the file records neither way to it."""
    if info.focal35:
        return _in_range(info, float(info.focal35), "FocalLengthIn35mmFilm")
    unit = UNIT_MM.get(int(info.plane_unit or 2))  # Exif's default unit is the inch
    if info.focal and info.plane_x and unit:
        w, h = ((info.exif_width, info.exif_height) if info.exif_width and info.exif_height else size)
        sensor = (w / info.plane_x * unit, h / (info.plane_y or info.plane_x) * unit)
        if not SENSOR_DIAGONAL[0] < math.hypot(*sensor) < SENSOR_DIAGONAL[1]:
            raise LensError(f"{info.path}: its focal plane (FocalPlaneXResolution) puts the {w:g}x{h:g} "
                            f"frame on a {sensor[0]:.4g} x {sensor[1]:.4g} mm sensor, no camera's (1 to 100 mm across "
                            "the diagonal), so its 35 mm equivalent is unknown (a copy made smaller loses it); give "
                            "the lens, e.g. --from perspective:fov=DEGREES")
        focal35 = info.focal * FRAME_DIAGONAL / math.hypot(*sensor)
        return _in_range(info, focal35, f"FocalLength {info.focal:g} mm on a {sensor[0]:.4g} x {sensor[1]:.4g} mm "
                         "sensor (FocalPlaneXResolution)")
    held = [text for text in (_held(info, "focal35"), None if info.focal else _held(info, "focal")) if text]
    absent = [tag for name, tag in (("focal35", "FocalLengthIn35mmFilm"), ("focal", "FocalLength"))
              if name not in info.held and not (name == "focal" and info.focal)]
    if not info.focal:
        missing = " and ".join(held + (["no " + " nor ".join(absent)] if absent else []))
    else:
        first, plane = (held[0] if held else "no FocalLengthIn35mmFilm"), _held(info, "plane_x")
        if plane or not info.plane_x:
            plane = f"and {plane}" if plane else "and no FocalPlaneXResolution" if held else "nor FocalPlaneXResolution"
            missing = f"{first}, {plane} to go with FocalLength {info.focal:g} mm"
        else:
            missing = f"{first}, and its FocalPlaneResolutionUnit {info.plane_unit:g} is no length to go with FocalLength"
    raise LensError(f"{info.path}: --from exif needs the photo's 35 mm equivalent focal length; its EXIF has "
                    f"{missing}; give the lens, e.g. --from perspective:fov=DEGREES")


#: what a recorded number that is no value means, by field (Exif 2.3: FocalLengthIn35mmFilm 0 is "unknown")
HELD = {"focal35": ("FocalLengthIn35mmFilm", ""), "focal": ("FocalLength", " mm"),
        "plane_x": ("FocalPlaneXResolution", "")}


def _held(info, name: str) -> str | None:
    """The text of a number the file records for ``name`` that is no value (``FocalLength 0 mm, no lens's``), as
    :attr:`~lenslab.lenses.lensfun.exif.PhotoLens.held` keeps it; None when the file records none."""
    shown = getattr(info, "held", {}).get(name)
    if shown is None:
        return None
    tag, unit = HELD[name]
    why = "Exif's 'unknown'" if name == "focal35" and shown == "0" else "no lens's" if name != "plane_x" else "no resolution"
    return f"{tag} {shown}{unit} ({why})"


def _in_range(info, focal35: float, source: str) -> tuple[float, str]:
    """``(focal35, source)`` where it is within :data:`FOCAL35_RANGE`, else the one-line :class:`LensError`."""
    lo, hi = FOCAL35_RANGE
    if not lo <= focal35 <= hi:
        raise LensError(f"{info.path}: its 35 mm equivalent focal length of {focal35:.4g} mm (from "
                        f"{source}) is no lens's (Exif records {lo:g} to {hi:g} mm); give the lens, e.g. --from "
                        "perspective:fov=DEGREES")
    return focal35, source


def exif_view(path, size: tuple[int, int], frame: tuple[int, int], crop_note: bool = True) -> ExifView:
    """The pinhole view of the photo at ``path`` whose image as shown (after its EXIF orientation) is
    ``size`` (W, H) and whose stored frame is ``frame`` (W, H, before its orientation: what the focal plane's
    resolution counts across; :func:`lenslab.io.exif_orientation.stored_size` reads it); with ``crop_note``, a
    note where that image looks cropped from the frame the EXIF records."""
    from lenslab.lenses.lensfun.exif import photo_lens

    w, h = int(size[0]), int(size[1])
    info = photo_lens(path)
    focal35, source = equivalent_focal(info, (int(frame[0]), int(frame[1])))
    if crop_note:
        note_crop(info, (w, h))
    return ExifView(focal35, source, (w, h))


def note_crop(info, size: tuple[int, int]) -> None:
    """A note where the frame the EXIF records (PixelXDimension x PixelYDimension) has another shape than the image
    (either way round: the image may be turned): a crop, whose field is narrower than the frame's."""
    fw, fh = info.exif_width, info.exif_height
    if not (fw and fh):
        return
    aspect = size[0] / size[1]
    if min(abs(aspect / (fw / fh) - 1), abs(aspect / (fh / fw) - 1)) <= 0.01:  # 1%: a copy rounded to whole pixels
        return
    import warnings

    warnings.warn(f"the image is {size[0]}x{size[1]} and its EXIF records a {fw:g}x{fh:g} frame: it looks "
                  "cropped, so it sees less than the field its focal length gives; give --from perspective:fov=... "
                  "if you know it", UserWarning, stacklevel=2)


def read_exif_lens(spec: str, size, frame_of):
    """``make_lens`` of ``exif:photo=PATH``: the pinhole of that photo's 35 mm equivalent focal length for an
    image of ``size`` (the photo's as shown, or a copy of its shape); ``frame_of(path, size)`` gives the photo's
    stored frame (:func:`lenslab.io.exif_orientation.stored_size`); plain ``exif`` names no photo here."""
    photo = exif_photo(spec)
    if photo is None:
        raise LensError("exif reads the lens from a photo's EXIF: give it as the --from of a command that reads the "
                        "photo (lenslab warp PHOTO --from exif), or name it: exif:photo=PHOTO")
    from lenslab.lenses.registry import make_lens

    if size is None:
        raise LensError(f"exif:photo={photo}: give the size of the image it is the lens of")
    view = exif_view(photo, size, frame_of(photo, size), crop_note=False)  # (any size: a map's, a check's)
    return make_lens(view.spec, view.size)
