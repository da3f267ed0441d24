"""Matching a photo's camera and lens to the lensfun database, mount- and crop-aware, saying what failed.

lensfun fits a lens to a camera when one of the lens's mounts is the camera's mount or one the camera's
mount takes (its ``compat`` list: a Canon EF-S body takes Canon EF lenses), and when the camera's crop
factor is at least 0.96 of the one the lens was calibrated at (lensfun's ``lens.cpp``: a profile
measured on a smaller sensor does not reach a larger sensor's corners). :func:`fits` says which of the
two fails; :func:`no_fit_message` turns that into the one-line error users read.
"""

from __future__ import annotations

from lenslab.errors import LensError
from lenslab.lenses import lensfun_db as ldb
from lenslab.lenses.exif_lens import PhotoLens, camera_name

#: lensfun's tolerance on crop factors (a lens fits a camera whose crop is at least this share of its own)
CROP_TOLERANCE = 0.96


def mounts_taken(camera) -> set[str]:
    """The mounts whose lenses a camera takes: its own and its mount's compatible ones."""
    out = {camera.mount}
    for m in ldb.database().mounts:
        if m.name == camera.mount:
            out |= set(m.compat or [])
    return out


def fits(lens, camera) -> tuple[bool, bool]:
    """(mount fits, crop fits) of a lensfun lens on a lensfun camera."""
    mount_ok = bool(set(lens.mounts or []) & mounts_taken(camera)) or not lens.mounts
    crop_ok = float(camera.crop_factor) >= CROP_TOLERANCE * float(lens.crop_factor)
    return mount_ok, crop_ok


def lens_label(lens) -> str:
    return camera_name(lens.maker, lens.model) or lens.model


def no_fit_message(lens, camera) -> str:
    """Why ``lens`` does not fit ``camera``, and what to give instead."""
    mount_ok, crop_ok = fits(lens, camera)
    cam = camera_name(camera.maker, camera.model)
    crop = float(camera.crop_factor)
    reasons = []
    if not mount_ok:
        reasons.append(f"the lens has mounts {', '.join(lens.mounts)}; the {cam} is {camera.mount}")
    if not crop_ok:
        reasons.append(f"the profile was measured at crop {float(lens.crop_factor):.4g}, larger than the {cam}'s "
                       f"{crop:.4g} (it does not reach this sensor's corners)")
    what = "; ".join(reasons) or f"lensfun does not pair it with the {cam}"
    other = example_camera(lens)
    hint = f'camera="{camera_name(other.maker, other.model)}"' if other is not None else "camera=..."
    return (f"lensfun: {lens_label(lens)} does not fit the {cam}: {what} with crop {crop:.4g}: give {hint} "
            f"(a camera it fits), or leave camera out and give crop={crop:.4g} to use the profile on this "
            f"sensor anyway (it was measured at crop {float(lens.crop_factor):.4g})")


def example_camera(lens):
    """A camera of the database the lens fits (its first mount first), or None."""
    best = None
    for cam in ldb.database().cameras:
        mount_ok, crop_ok = fits(lens, cam)
        if mount_ok and crop_ok and (best is None or abs(cam.crop_factor - lens.crop_factor)
                                     < abs(best.crop_factor - lens.crop_factor)):
            best = cam
    return best


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
