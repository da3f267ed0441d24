"""A photo's camera EXIF carried to the images ``lenslab convert`` and ``lenslab tonemap`` make of it.

**What is carried: a whitelist** (:data:`lenslab.exif_tags.TAGS`), never the whole block: the camera (Make,
Model), the lens (LensMake, LensModel, FocalLength, FocalLengthIn35mmFilm, the focal plane's X and Y resolution and
its unit), the frame (PixelXDimension, PixelYDimension), the shot (DateTimeOriginal, OffsetTimeOriginal,
ExposureTime, FNumber, PhotographicSensitivity, SubjectDistance) and Orientation. Left out: GPS (where the photo
was taken: private, and no lens or colour depends on it), the thumbnail (a picture of pixels that may have
changed), maker notes (opaque, and their offsets break when moved), and everything else. A whitelist also bounds
what a hostile block can put into an output.

**The frame the tags describe is the output's.** The pixels written are the image as read: a JPEG's and a HEIC's
as shown (their orientation applied on reading), so Orientation is 1; an EXR's, a TIFF's and a PNG's as stored, so
the photo's Orientation stays and the copy is shown as the photo is. PixelXDimension x PixelYDimension are the
output's size. The
focal plane's resolution counts pixels per unit across the stored frame: for a turned photo X and Y change places,
and for an output of another size (a resize of the whole frame) it is scaled with the pixels, so the sensor it
gives stays the same size; FocalLengthIn35mmFilm, a field of view across the whole frame, stays as it is. For an
output that is part of the frame (an EXR's data window written alone), FocalLengthIn35mmFilm no longer holds and
is left out; the focal plane's resolution keeps its pixel pitch, and with FocalLength gives that part's field.
``--from exif`` on the output so gives the field of view it gives on the photo.

**Where it goes**: JPEG (an ``APP1 Exif`` segment), PNG (an ``eXIf`` chunk), TIFF (the first IFD's Make, Model and
Orientation, and an Exif IFD without PixelXDimension and PixelYDimension, which Exif gives compressed images only)
and EXR (header attributes under OpenImageIO's names: ``Make``, ``Model``, ``Exif:FocalLengthIn35mmFilm``...), each
with the tags Exif 2.32 requires of it (:mod:`lenslab.io.exif.outputs`). Radiance HDR, PFM and PPM have no place
for it.

**A damaged or huge block** (over :data:`lenslab.io.exif.sources.MAX_BYTES`) is left out with one note; the image
is written all the same. Tags of a type or value no camera writes are left out and named in that note.
"""

from __future__ import annotations

import struct
from fractions import Fraction

from lenslab.io.exif.ifd import Damaged
from lenslab.io.exif.sources import TooLarge


class ExifNote(UserWarning):
    """A photo's EXIF (or some of its tags) was not carried to its output; ``command_line``: the note without
    the path (a command's note names the file)."""


def _note(path, text: str) -> None:
    import warnings

    warning = ExifNote(f"{path}: {text}")
    warning.command_line = text
    warnings.warn(warning, stacklevel=3)


def camera_tags(path) -> dict:
    """The carried tags of the photo at ``path`` ({} where it holds none); a damaged or huge block, or tags no
    camera writes, are said in one note."""
    from lenslab.io.exif.sources import read_tags
    from lenslab.io.registry import sniff

    try:
        found = read_tags(path, sniff(path))
    except (Damaged, TooLarge) as exc:
        _note(path, f"its EXIF is not carried to the output: {exc}")
        return {}
    except (OSError, ValueError, struct.error, EOFError, RuntimeError) as exc:  # a damaged container, a codec's error
        _note(path, f"its EXIF is not carried to the output: it cannot be read ({exc})")
        return {}
    if found is None:
        return {}
    tags, odd = found
    if odd:
        _note(path, f"its EXIF's {', '.join(odd)} (of a type or value no camera writes) not carried to the output")
    return tags


def fitted(tags: dict, frame: tuple[int, int], turned: bool, out: tuple[int, int], whole: bool = True,
           upright: bool = True) -> dict:
    """``tags`` (of a photo whose stored frame is ``frame``, W x H; ``turned``: shown turned a quarter, its EXIF
    orientation 5 to 8) for an output of ``out`` (W x H) pixels as shown, stored upright: the whole frame resized
    (``whole``), or a part of it at the same pixel pitch. ``upright``: the pixels were read with the photo's
    orientation applied (a JPEG's, a HEIC's), so the output's is 1; else they are as stored, and it keeps the photo's.

    >>> from fractions import Fraction as F
    >>> t = fitted({"FocalPlaneXResolution": F(400), "FocalPlaneYResolution": F(300), "FocalLengthIn35mmFilm": 26},
    ...            (4000, 3000), True, (1500, 2000))
    >>> t["FocalPlaneXResolution"], t["FocalPlaneYResolution"], t["PixelXDimension"], t["Orientation"]
    (Fraction(150, 1), Fraction(200, 1), 1500, 1)
    """
    tags = dict(tags)
    fw, fh = ((tags["PixelXDimension"], tags["PixelYDimension"])
              if tags.get("PixelXDimension") and tags.get("PixelYDimension") else frame)
    px = tags.get("FocalPlaneXResolution")
    py = tags.get("FocalPlaneYResolution") or px
    if turned:  # the stored frame's width is the output's height
        fw, fh, px, py = fh, fw, py, px
    w, h = int(out[0]), int(out[1])
    if px:
        scale = (Fraction(w, fw), Fraction(h, fh)) if whole else (1, 1)
        tags["FocalPlaneXResolution"], tags["FocalPlaneYResolution"] = px * scale[0], py * scale[1]
    if not whole:
        tags.pop("FocalLengthIn35mmFilm", None)
    tags.update(PixelXDimension=w, PixelYDimension=h, **({"Orientation": 1} if upright else {}))
    return tags


def carried(path, meta: dict, out: tuple[int, int], fmt, full: tuple[int, int] | None = None) -> dict:
    """The write option that carries the EXIF of the photo at ``path`` (read as ``meta``, shown at ``full``, W x H;
    default ``out``) to an output of format record ``fmt`` of ``out`` pixels: ``{"exif": tags}``, or {} where the
    format has no place for it or the photo holds none."""
    if "exif" not in fmt.write_options:
        return {}
    if meta.get("format") == "exr" and "attributes" in meta:  # the header read with the pixels (the part read)
        from lenslab.exif_tags import exr_tags

        tags = exr_tags(meta["attributes"])
    else:
        tags = camera_tags(path)
    if not tags:
        return {}
    from lenslab.io.exif_orientation import stored_size

    shown = tuple(full or out)
    frame = tuple(stored_size(path, shown))
    recorded = (tags.get("PixelXDimension"), tags.get("PixelYDimension"))  # the frame the focal plane describes
    # turned: shown turned a quarter from the frame stored, or from the one its EXIF records (a JPEG turned losslessly,
    # its Orientation reset to 1; a HEIC whose irot libheif applies; such a photo made smaller keeping its EXIF)
    turned = int(meta.get("exif_orientation") or 1) >= 5 or _crosswise(frame, shown) or _crosswise(recorded, shown)
    upright = meta.get("format") in ORIENTED  # (an EXR, TIFF or PNG is read as stored: its Orientation stays)
    return {"exif": fitted(tags, frame, turned, out, whole=tuple(out) == shown, upright=upright)}


#: the formats lenslab reads with their orientation applied: a JPEG's EXIF Orientation, a HEIC's irot (libheif)
ORIENTED = ("jpg", "heif")


def _crosswise(frame, shown) -> bool:
    """Whether ``frame`` (W, H; None or 0 where unknown) is ``shown`` (W, H) turned a quarter: its shape nearer the
    turned shape than the shown one (a frame of the same shape, or a square one, is not)."""
    if not all(frame) or frame[0] == frame[1] or shown[0] == shown[1]:
        return False
    aspect = frame[0] / frame[1]
    return abs(aspect - shown[1] / shown[0]) < abs(aspect - shown[0] / shown[1])


__all__ = ["ExifNote", "camera_tags", "carried", "fitted"]
