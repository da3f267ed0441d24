"""Calibration files of other tools, read and written as lenslab lenses: one plugin per format.

``read_lens("cal.yaml")`` reads OpenCV FileStorage YAML/JSON (``cv2.FileStorage``), Kalibr camchain
YAML, COLMAP ``cameras.txt`` (``cameras.txt#2`` picks camera 2), OCamCalib ``calib_results.txt`` and
lenslab's camera TOML; ``write_lens(path, lens)`` writes one. Each plugin converts pixel conventions at
its boundary (see ``docs/conventions.md``, "Calibrated cameras"). Every problem with a file is a
one-line :class:`CameraFileError` naming the file and the key; a camera a format cannot hold is a
:class:`~lenslab.errors.LensError` (the user's choice of format).
"""

from __future__ import annotations

import importlib
from pathlib import Path

from lenslab.errors import LenslabError, LensError, UsageError
from lenslab.lens_sources import add_source
from lenslab.registry import Registry


class CameraFileError(LenslabError, ValueError):
    """A camera file is missing, unreadable, or lacks or misuses a key (the message names the file and
    the key). A failed input, not a usage error: commands exit with status 1."""


class NoCameraError(CameraFileError, UsageError):
    """An image named where a camera is expected records none: it cannot be a lens, a usage mistake (exit 2)."""

#: format name -> plugin module (in lenslab.calibfiles); the order is the order of sniffing (an OpenCV
#: FileStorage file is tested before a Kalibr camchain, which is YAML too)
FORMATS: Registry[str] = Registry("calibration format", LensError)
FORMATS.add("opencv", "opencv", summary="OpenCV FileStorage YAML/JSON (cv2.FileStorage)",
            references=("OpenCV calibration sample (fisheye_model: 1)",))
FORMATS.add("kalibr", "kalibr", summary="Kalibr camchain YAML", aliases=("camchain",))
FORMATS.add("colmap", "colmap", summary="COLMAP cameras.txt (FILE#ID picks a camera)")
FORMATS.add("ocam", "ocamcalib", summary="OCamCalib calib_results.txt", aliases=("ocamcalib",))
FORMATS.add("toml", "toml", summary="lenslab camera TOML")
SUFFIXES = (".yaml", ".yml", ".json", ".xml", ".txt", ".toml")


def plugin(name: str):
    return importlib.import_module(f"lenslab.calibfiles.{FORMATS.lookup(name)}")


def split_pick(spec: str) -> tuple[Path, str | None]:
    """``FILE#ID`` -> (FILE, ID); ``FILE`` -> (FILE, None)."""
    path, sep, pick = str(spec).partition("#")
    return Path(path), (pick.strip() or None) if sep else None


def is_camera_file(spec) -> bool:
    """True when a camera spec names a file (an existing one, or a calibration file's name)."""
    if not isinstance(spec, str) or not spec.strip():
        return False
    from lenslab.lenses.registry import REGISTRY

    path, _ = split_pick(spec.strip())
    try:
        exists = path.is_file()
    except OSError:  # a name too long for a file: a lens spec
        exists = False
    if not exists and spec.partition(":")[0].strip().lower() in REGISTRY:
        return False  # a model spec such as fisheye:fov=180
    return exists or (":" not in spec and (path.suffix.lower() in SUFFIXES or _names_a_file(path)))


def _names_a_file(path: Path) -> bool:
    """A name no lens model has, that only a file can have: with a folder (``dir/cam``) or an image's extension."""
    from lenslab.io.registry import input_extensions

    return len(path.parts) > 1 or path.suffix.lower() in input_extensions()


def sniff(path: Path, text: str) -> str:
    """The format of a file, from its content (then its name)."""
    for name in FORMATS:
        if plugin(name).sniff(path, text):
            return name
    raise CameraFileError(f"{path}: not a calibration file lenslab knows (OpenCV YAML/JSON, Kalibr camchain, "
                    "COLMAP cameras.txt, OCamCalib calib_results.txt or lenslab TOML)")


#: the largest camera file read (a real one holds a few kilobytes)
MAX_CAMERA_FILE = 4 << 20


def read_text(path: Path) -> str:
    from lenslab.errors import InputError
    from lenslab.inputs.sidefile import read_side_text

    try:
        return read_side_text(path, "camera file", MAX_CAMERA_FILE)
    except FileNotFoundError:
        raise CameraFileError(f"{path}: no such file or directory") from None
    except InputError as exc:
        raise CameraFileError(str(exc)) from None


def image_lens(path: Path):
    """The lens an image file records (an EXR written by lenslab or tracer), None when ``path`` is no image; an
    image without a camera is a :class:`CameraFileError` that says where a camera comes from."""
    camera = image_camera(path)
    return None if camera is None else camera.lens


def image_camera(path: Path):
    """The camera (lens and pose) an image file records, as :func:`image_lens` reads it."""
    from lenslab.io.registry import get, sniff

    try:
        fmt = sniff(path) if path.is_file() else None
    except (LenslabError, OSError):  # not an image: a calibration file
        return None
    if fmt is None:
        return None
    from lenslab.io import read

    camera = read(path)[1].get("camera")
    if camera is None:
        raise NoCameraError(f"{path}: this {get(fmt).title} image records no camera, so it cannot be a lens; give a "
                            "lens spec (e.g. equirect, fisheye:fov=180) or a calibration file instead (EXR files "
                            "written by lenslab and tracer carry their camera)")
    return camera


def read_lenses(spec: str) -> tuple[str, list[tuple[str, object]]]:
    """The format and every camera of a file as ``(id, lens)`` pairs (an image's recorded camera is ``0``)."""
    path, _ = split_pick(spec)
    lens = image_lens(path)
    if lens is not None:
        return "image", [("0", lens)]
    text = read_text(path)
    fmt = sniff(path, text)
    return fmt, plugin(fmt).read(path, text)


def read_lens(spec: str, size: tuple[int, int] | None = None):
    """The lens of a camera file (``FILE#ID`` picks one of several), scaled to ``size`` if given."""
    path, pick = split_pick(spec)
    _, cams = read_lenses(spec)
    if pick is not None:
        found = [lens for cid, lens in cams if cid == pick]
        if not found:
            ids = [cid for cid, _ in cams]
            raise CameraFileError(f"{path}: no camera {pick!r}; its camera ID{'s' if len(ids) > 1 else ''}: "
                                  f"{', '.join(ids)}")
        lens = found[0]
    elif len(cams) == 1:
        lens = cams[0][1]
    else:
        raise CameraFileError(f"{path}: holds {len(cams)} cameras; pick one as {path}#ID "
                        f"(IDs: {', '.join(cid for cid, _ in cams)})")
    if size is not None and tuple(size) != (lens.width, lens.height):
        lens = lens.with_size(*size)
    return lens


def default_format(path: Path, lens) -> str:
    """The format a file name asks for: .toml lenslab, .txt COLMAP (OCamCalib for ocam), .yaml/.json
    OpenCV (Kalibr for double-sphere and eucm, which OpenCV has not)."""
    suffix = path.suffix.lower()
    if suffix == ".toml":
        return "toml"
    if suffix == ".txt":
        return "ocam" if lens.name == "ocam" else "colmap"
    if suffix in (".yaml", ".yml", ".json", ".xml"):
        return "kalibr" if lens.name in ("double-sphere", "eucm") and suffix in (".yaml", ".yml") else "opencv"
    raise LensError(f"{path}: cannot tell the format from the name; use .yaml/.json (OpenCV), .txt (COLMAP or "
                    "OCamCalib), .toml (lenslab), or say --format")


def write_lens(path, lens, fmt: str | None = None, overwrite: bool = False) -> Path:
    """Write ``lens`` as a calibration file (atomically); the format from ``fmt`` or the file name."""
    from lenslab.atomic import atomic_write_path

    path = Path(path)
    fmt = fmt or default_format(path, lens)
    mod = plugin(fmt)
    with atomic_write_path(path, overwrite=overwrite) as tmp:
        try:
            mod.write(tmp, lens)
        except LensError as exc:  # a model the format has no place for: named by the user's file, not the temporary
            raise LensError(f"{path}: {exc}") from None
    return path


add_source(is_camera_file, read_lens)  # make_lens and Camera.from_spec take FILE and FILE#ID
