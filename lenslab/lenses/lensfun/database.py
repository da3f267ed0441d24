"""The lensfun database: find lenses and cameras, and read a lens's profile at given settings.

lensfunpy (the ``lenslab[lensfun]`` extra) reads the XML database and interpolates the distortion,
TCA and vignetting coefficients between calibrated focal lengths, apertures and distances exactly
as lensfun does; lenslab's own float64 models (:mod:`lenslab.lenses.lensfun.profile`) use them.
The two facts lensfunpy does not expose, a profile's sensor aspect ratio and its real focal lengths,
are read from the same XML files and interpolated as lensfun's ``lens.cpp`` does.

lensfun fits a lens to a camera when one of the lens's mounts is the camera's mount or one the camera's
mount takes (its ``compat`` list: a Canon EF-S body takes Canon EF lenses), and when the camera's crop
factor is at least 0.96 of the one the lens was calibrated at (lensfun's ``lens.cpp``: a profile
measured on a smaller sensor does not reach a larger sensor's corners). :func:`fits` says which of the
two fails; :func:`no_fit_message` turns that into the one-line error users read.

By default the bundled database (lensfun 0.3.4, as shipped in the lensfunpy wheel) is loaded. Your
own XML files come in through ``LENSLAB_LENSFUN_DB`` (directories or files, separated by ``os.pathsep``)
or ``lenslab lenses --lensfun-db DIR``; ``LENSLAB_LENSFUN_BUNDLED=0`` leaves the bundled ones out.
"""

from __future__ import annotations

import contextlib
import functools
import os
from dataclasses import dataclass, field
from pathlib import Path

from lenslab.errors import LensError
from lenslab.lenses.lensfun.exif import camera_name

ENV_DB = "LENSLAB_LENSFUN_DB"
ENV_BUNDLED = "LENSLAB_LENSFUN_BUNDLED"

#: lensfun's lens types, by lensfunpy's enum name -> lenslab's word for the projection
TYPES = {
    "RECTILINEAR": "rectilinear", "FISHEYE": "fisheye", "PANORAMIC": "panoramic",
    "EQUIRECTANGULAR": "equirectangular", "FISHEYE_ORTHOGRAPHIC": "orthographic",
    "FISHEYE_STEREOGRAPHIC": "stereographic", "FISHEYE_EQUISOLID": "equisolid", "FISHEYE_THOBY": "thoby",
}


def lensfunpy():
    try:
        import lensfunpy as lf
    except ImportError:
        raise LensError("lensfun profiles need lensfunpy: pip install 'lenslab[lensfun]'") from None
    return lf


def user_paths() -> list[Path]:
    """The user's XML files from ``LENSLAB_LENSFUN_DB``."""
    out: list[Path] = []
    for item in filter(None, os.environ.get(ENV_DB, "").split(os.pathsep)):
        p = Path(item).expanduser()
        if p.is_dir():
            out += sorted(p.glob("*.xml"))
        elif p.is_file():
            out.append(p)
        else:
            raise LensError(f"lensfun database {item!r}: no such file or directory")
    return out


def use_database(paths: list[str], bundled: bool = True) -> None:
    """Point this process's lensfun lookups at ``paths`` (XML files or directories) and, unless
    ``bundled`` is False, the bundled database too."""
    os.environ[ENV_DB] = os.pathsep.join(str(p) for p in paths)
    os.environ[ENV_BUNDLED] = "1" if bundled else "0"
    _database.cache_clear()
    _xml_facts.cache_clear()


@contextlib.contextmanager
def using_database(paths: list[str], bundled: bool = True):
    """:func:`use_database` for the duration of a ``with`` block; the settings before it come back after."""
    before = {k: os.environ.get(k) for k in (ENV_DB, ENV_BUNDLED)}
    use_database(paths, bundled)
    try:
        yield
    finally:
        for k, v in before.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def bundled_dir() -> Path:
    return Path(lensfunpy().__file__).parent / "db_files"


def xml_files() -> list[Path]:
    files = user_paths()
    if os.environ.get(ENV_BUNDLED, "1") != "0":
        files = sorted(bundled_dir().glob("*.xml")) + files
    return files


def settings() -> tuple[str, str]:
    """The current database settings (your files, bundled or not): the key of every cache here."""
    return os.environ.get(ENV_DB, ""), os.environ.get(ENV_BUNDLED, "1")


def database():
    """The lensfunpy database for the current settings (cached)."""
    return _database(*settings())


@functools.lru_cache(maxsize=4)
def _database(_db: str, bundled: str):
    lf = lensfunpy()
    paths = [str(p) for p in user_paths()]
    try:
        return lf.Database(paths=paths or None, load_common=False, load_bundled=bundled != "0")
    except Exception as exc:  # lensfunpy raises its own errors for unreadable XML
        raise LensError(f"lensfun database: {exc}") from None


# -- search -----------------------------------------------------------------------------------
def find_cameras(query: str) -> list:
    """Cameras matching ``query`` ("canon eos 5d mark ii", "nikon d750"...), best first.

    lensfun's own fuzzy search on maker and model; a query whose first word is the maker is tried
    split that way too."""
    db = database()
    words = query.split()
    found = list(db.find_cameras(None, query, loose_search=True) or [])
    if len(words) > 1:
        found += list(db.find_cameras(words[0], " ".join(words[1:]), loose_search=True) or [])
    if not found:  # every word somewhere in "maker model"
        low = [w.lower() for w in words]
        found = [c for c in db.cameras if all(w in f"{c.maker} {c.model}".lower() for w in low)]
    seen, out = set(), []
    for c in found:
        key = (c.maker, c.model, c.variant)
        if key not in seen:
            seen.add(key)
            out.append(c)
    exact = [c for c in out if c.model.lower() == query.strip().lower()]
    return exact + [c for c in out if c not in exact]


def find_lenses(query: str, camera=None) -> list:
    """Lenses matching ``query`` with lensfun's fuzzy search, best score first; with ``camera``,
    only those that fit it (mount and sensor), as lensfun decides."""
    db = database()
    if camera is not None:
        cams = [camera]
    else:  # lensfun needs a camera: ask once per mount with its smallest sensor, so every lens can fit
        per_mount: dict[str, object] = {}
        for c in db.cameras:
            if c.mount not in per_mount or c.crop_factor > per_mount[c.mount].crop_factor:
                per_mount[c.mount] = c
        cams = list(per_mount.values())
    seen, out = set(), []
    for cam in cams:
        for lens in db.find_lenses(cam, None, query, loose_search=False) or []:
            key = (lens.maker, lens.model, round(lens.crop_factor, 4))
            if key not in seen:
                seen.add(key)
                out.append(lens)
    if not out and camera is None:  # lenses of a mount no camera in the database has: every word in the name
        low = query.lower().split()
        out = [l for l in db.lenses if all(w in f"{l.maker} {l.model}".lower() for w in low)]
    out.sort(key=lambda l: -l.score)
    exact = [l for l in out if l.model.lower() == query.strip().lower()]
    return exact + [l for l in out if l not in exact]


def pick_lens(query: str, camera=None):
    found = find_lenses(query, camera)
    if not found:
        if camera is not None and find_lenses(query):  # the lens is there, for other mounts or sensors
            raise LensError(no_fit_message(find_lenses(query)[0], camera))
        where = f" for the {camera_name(camera.maker, camera.model)}" if camera is not None else ""
        raise LensError(f"lensfun: no lens matches {query!r}{where}; try 'lenslab lenses --lensfun \"WORDS\"'")
    if len(found) > 1 and found[0].model.lower() != query.strip().lower() and found[0].score == found[1].score:
        names = "; ".join(f"{l.maker} {l.model}" for l in found[:8])
        raise LensError(f"lensfun: {query!r} matches several lenses equally well ({names}); give more of the name")
    return found[0]


def pick_camera(query: str):
    found = find_cameras(query)
    if not found:
        raise LensError(f"lensfun: no camera matches {query!r}; try 'lenslab lenses --lensfun \"WORDS\"' or give crop=")
    return found[0]


# -- which lens fits which camera --------------------------------------------------------------------
#: lensfun's tolerance on crop factors (a lens fits a camera whose crop is at least this share of its own)
CROP_TOLERANCE = 0.96


def mounts_taken(camera) -> set[str]:
    """The mounts whose lenses a camera takes: its own and its mount's compatible ones."""
    out = {camera.mount}
    for m in database().mounts:
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
    for cam in database().cameras:
        mount_ok, crop_ok = fits(lens, cam)
        if mount_ok and crop_ok and (best is None or abs(cam.crop_factor - lens.crop_factor)
                                     < abs(best.crop_factor - lens.crop_factor)):
            best = cam
    return best


# -- facts lensfunpy does not expose ---------------------------------------------------------------
@dataclass(frozen=True)
class XmlFacts:
    aspect: float = 1.5  # lensfun's default for a lens profile
    real_focal: tuple[tuple[float, float], ...] = field(default_factory=tuple)  # (focal, real focal)


def xml_facts(maker: str, model: str, crop: float) -> XmlFacts:
    return _xml_facts(*settings()).get(
        (maker.lower(), model.lower(), round(crop, 3)), XmlFacts())


@functools.lru_cache(maxsize=4)
def _xml_facts(_db: str, _bundled: str) -> dict:
    from lenslab.inputs.safeload import load_xml
    from lenslab.inputs.sidefile import read_side_bytes

    out = {}
    for path in xml_files():  # no DTD or entity, bounded depth and size
        root = load_xml(read_side_bytes(path, "lensfun database", 64 << 20), f"lensfun database {path}", LensError)
        for lens in root.iter("lens"):
            maker = next((m.text for m in lens.findall("maker") if not m.get("lang")), "") or ""
            model = next((m.text for m in lens.findall("model") if not m.get("lang")), "") or ""
            crop_text = lens.findtext("cropfactor")
            crop = float(crop_text) if crop_text else 1.0
            aspect = parse_aspect(lens.findtext("aspect-ratio"))
            real = tuple(
                (float(e.get("focal")), float(e.get("real-focal")))
                for e in lens.iter("real-focal-length") if e.get("focal") and e.get("real-focal")
            )
            out[(maker.strip().lower(), model.strip().lower(), round(float(f"{crop:.7g}"), 3))] = XmlFacts(aspect, real)
    return out


def parse_aspect(text: str | None) -> float:
    """``"4:3"`` or ``"1.333"`` -> 1.333...; lensfun's default 1.5 when absent."""
    if not text or not text.strip():
        return 1.5
    a, colon, b = text.partition(":")
    return float(a) / float(b) if colon else float(a)


def hermite(y1: float | None, y2: float, y3: float, y4: float | None, t: float) -> float:
    """lensfun's interpolation between calibrations y2 (t=0) and y3 (t=1), with neighbours y1, y4
    (None when missing): a cubic Hermite spline with central-difference tangents."""
    tg2 = (y3 - y2) if y1 is None else (y3 - y1) * 0.5
    tg3 = (y3 - y2) if y4 is None else (y4 - y2) * 0.5
    t2, t3 = t * t, t * t * t
    return (2 * t3 - 3 * t2 + 1) * y2 + (t3 - 2 * t2 + t) * tg2 + (-2 * t3 + 3 * t2) * y3 + (t3 - t2) * tg3


def interpolate_real_focal(table: tuple[tuple[float, float], ...], focal: float) -> float | None:
    """Real focal length at ``focal`` from (focal, real) calibrations: exact match, nearest one on a
    single side, or the Hermite spline through the two nearest on each side."""
    table = tuple((f, r) for f, r in table if r != 0)
    if not table:
        return None
    for f, r in table:
        if f == focal:
            return r
    below = sorted((p for p in table if p[0] < focal), key=lambda p: focal - p[0])[:2]
    above = sorted((p for p in table if p[0] > focal), key=lambda p: p[0] - focal)[:2]
    if not below or not above:
        return (below or above)[0][1]
    f2, y2 = below[0]
    f3, y3 = above[0]
    y1 = below[1][1] if len(below) > 1 else None
    y4 = above[1][1] if len(above) > 1 else None
    return hermite(y1, y2, y3, y4, (focal - f2) / (f3 - f2))


# -- what a profile holds ----------------------------------------------------------------------------
def _focals(entries) -> str:
    fs = sorted({float(e.focal) for e in entries})
    return ", ".join(f"{f:g}" for f in fs) + " mm"


def describe_lens(lens) -> list[str]:
    """Lines saying what a lensfun profile holds, for ``lenslab lenses --lensfun``."""
    def rng(a, b, unit=""):
        a, b = (float(v) if v else 0.0 for v in (a, b))
        return (f"{a:g}" if not b or a == b else f"{a:g}-{b:g}") + unit if a else "?"

    facts = xml_facts(lens.maker, lens.model, float(lens.crop_factor))
    quoted = f'"{lens.model}"' if "," in lens.model else lens.model
    lines = [f"{lens.maker}: {lens.model}",
             f"  spec        lensfun:lens={quoted}",
             f"  type        {TYPES.get(lens.type.name, lens.type.name.lower())}, crop factor {float(lens.crop_factor):g}, "
             f"aspect {facts.aspect:.4g}, focal {rng(lens.min_focal, lens.max_focal, ' mm')}, "
             f"f/{rng(lens.min_aperture, lens.max_aperture)}"]
    dist = list(lens.calib_distortion or [])
    models = sorted({e.model.name.lower() for e in dist})
    lines.append(f"  distortion  {'/'.join(models)} at {_focals(dist)}" if dist else "  distortion  none")
    tca = list(lens.calib_tca or [])
    models = sorted({e.model.name.lower() for e in tca})
    lines.append(f"  tca         {'/'.join(models)} at {_focals(tca)}" if tca else "  tca         none")
    vig = list(lens.calib_vignetting or [])
    if vig:
        aps = sorted({float(e.aperture) for e in vig})
        dists = sorted({float(e.distance) for e in vig})
        lines.append(f"  vignetting  pa, {len(vig)} entries; focal {_focals(vig)}; "
                     f"aperture {', '.join(f'f/{a:g}' for a in aps)}; distance {', '.join(f'{d:g}' for d in dists)} m")
    else:
        lines.append("  vignetting  none")
    if facts.real_focal:
        lines.append("  real focal  " + ", ".join(f"{f:g} -> {r:g} mm" for f, r in facts.real_focal))
    return lines


def describe_camera(cam) -> str:
    variant = f" ({cam.variant})" if getattr(cam, "variant", None) else ""
    return f"{cam.maker}: {cam.model}{variant}, mount {cam.mount}, crop factor {float(cam.crop_factor):g}"
