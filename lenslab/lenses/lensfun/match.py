"""A photo's camera and lens matched to the lensfun database: ``lensfun:auto``, ``info``'s profile line,
and ``lenslab lenses --lensfun`` search (lenses first, then only cameras they fit).

Whether a lens fits a camera, and the message when not, are :func:`lenslab.lenses.lensfun.database.fits`
and :func:`lenslab.lenses.lensfun.database.no_fit_message`.
"""

from __future__ import annotations

import re

from lenslab.errors import LensError
from lenslab.lenses.lensfun import database as ldb
from lenslab.lenses.lensfun.exif import PhotoLens, photo_lens
from lenslab.lenses.lensfun.database import fits, no_fit_message

def find_camera(maker: str | None, model: str | None):
    """The lensfun camera of an EXIF maker and model (lensfun knows EXIF's maker spellings), or None."""
    db = ldb.database()
    if not model:
        return None
    for loose in (False, True):
        found = db.find_cameras(maker or None, model, loose_search=loose) or []
        if found:
            return found[0]
    return None


def find_lens(info: PhotoLens, camera):
    """The lensfun lens a photo names, on its camera if known: (lens, None), or (None, message)."""
    query = info.lens_model
    fitting = ldb.find_lenses(query, camera) if camera is not None else []
    exact = [l for l in fitting if l.model.lower() == query.lower()]
    if exact or fitting:
        return (exact or fitting)[0], None
    anywhere = ldb.find_lenses(query)
    exact = [l for l in anywhere if l.model.lower() == query.lower()]
    if camera is not None and (exact or anywhere):
        return None, no_fit_message((exact or anywhere)[0], camera)
    if exact or anywhere:
        return (exact or anywhere)[0], None
    return None, (f"lensfun: no lens in the database matches {query!r} (from {info.path}); "
                  "try 'lenslab lenses --lensfun \"WORDS\"' and give lens=NAME")


def match_photo(info: PhotoLens, given: dict) -> str:
    """The explicit ``lensfun:`` spec for a photo's metadata; ``given`` values win."""
    values = dict(given)
    if not values.get("lens"):
        if not info.lens_model:
            raise LensError(f"{info.path}: the file records no lens model (EXIF LensModel, XMP aux:Lens); "
                            "give lensfun:lens=NAME")
    camera = None
    if not values.get("camera") and not values.get("crop"):
        camera = find_camera(info.camera_maker, info.camera_model)
        if camera is None and info.crop is None:
            what = info.camera or "no camera"
            raise LensError(f"{info.path}: lensfun does not know the camera ({what}) and the file records no "
                            "35 mm equivalent focal length: give crop=CROP_FACTOR (or camera=NAME)")
    elif values.get("camera"):
        camera = ldb.pick_camera(str(values["camera"]))
    if not values.get("lens"):
        lens, problem = find_lens(info, camera)
        if lens is None:
            raise LensError(problem)
        values["lens"] = lens.model
    if camera is not None:
        values.setdefault("camera", camera.model)
    elif not values.get("crop") and info.crop is not None:
        values["crop"] = round(info.crop, 4)
    for key in ("focal", "aperture", "distance"):
        if not values.get(key) and getattr(info, key):
            values[key] = getattr(info, key)
    return spec_text(values)


def spec_text(values: dict) -> str:
    order = ("lens", "camera", "crop", "focal", "aperture", "distance", "effects")
    parts = []
    for key in order + tuple(k for k in values if k not in order):
        if key not in values or values[key] in (None, ""):
            continue
        v = values[key]
        text = f"{float(v):g}" if isinstance(v, (int, float)) else str(v)
        parts.append(f'{key}="{text}"' if "," in text else f"{key}={text}")
    return "lensfun:" + ",".join(parts)


def search(query: str) -> tuple[list, list]:
    """``lenslab lenses --lensfun QUERY``: matching lenses, and the cameras that match the query and fit
    at least one of them (every camera that matches when no lens does)."""
    lenses = ldb.find_lenses(query)
    words = [w.lower() for w in query.split()]
    named = [c for c in ldb.database().cameras
             if all(w in f"{c.maker} {c.model} {c.variant or ''}".lower() for w in words)]
    if not lenses:
        return [], named or ldb.find_cameras(query)
    return lenses, [c for c in named if any(all(fits(l, c)) for l in lenses)]


def auto_spec(spec: str, path) -> str:
    """The explicit ``lensfun:`` spec for ``lensfun:auto[,key=value...]`` (or ``auto``) and the photo at
    ``path``: values the spec gives win over the file's."""
    from lenslab.lenses.registry import parse_spec

    rest = re.sub(r"^\s*(lensfun:)?auto\s*,?", "", spec, count=1)
    given = dict(parse_spec("lensfun:" + rest)[1]) if rest.strip() else {}
    return match_photo(photo_lens(path), given)


def metadata_report(path, size: tuple[int, int] | None = None, frame: tuple[int, int] | None = None) -> dict | None:
    """What ``lenslab info`` shows: the lens the file names, the profile lensfun:auto would use (or why none),
    and, for the image as shown at ``size`` (stored as ``frame``, before its EXIF orientation), the pinhole
    ``--from exif`` gives (or why none); None when the file names no lens, camera nor focal length."""
    try:
        info = photo_lens(path)
    except (LensError, OSError):
        return None
    if not (info.lens_model or info.camera_model or info.focal or info.focal35):
        return None
    out = {"found": info.describe(), "profile": None, "problem": None, "exif": None, "exif_problem": None}
    if info.lens_model or info.camera_model:
        try:
            out["profile"] = auto_spec("lensfun:auto", path)
        except LensError as exc:
            out["problem"] = str(exc)
    if size is not None:
        from lenslab.lenses.exif_view import exif_view

        try:
            out["exif"] = exif_view(path, size, frame or size).describe()
        except LensError as exc:
            out["exif_problem"] = str(exc)
    return out
