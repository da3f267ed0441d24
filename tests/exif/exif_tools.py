"""What the EXIF tests share: photos whose EXIF exiftool writes, exiftool's and OpenImageIO's readings, the
commands run in this process, and the field of view ``--from exif`` gives (from ``lenslab warp``'s own note)."""

from __future__ import annotations

import json
import math
import re
import shutil
import subprocess

import numpy as np
import pytest

EXIFTOOL = shutil.which("exiftool")
needs_exiftool = pytest.mark.skipif(EXIFTOOL is None, reason="exiftool (Debian's libimage-exiftool-perl) not installed")
#: exiftool's FOV turns radians to degrees with pi written 3.14159 (its Composite FOV: "$fd2 * 360 / 3.14159")
EXIFTOOL_PI = 3.14159
#: the formats ``lenslab convert`` writes that have a standard place for EXIF, by extension
OUTPUTS = ("jpg", "tif", "png", "exr")


def exiftool(path, *tags: str) -> dict:
    """exiftool's numeric values (``-n``) of ``tags`` (all of them when none is named) in ``path``."""
    out = subprocess.run([EXIFTOOL, "-j", "-n", *(f"-{t}" for t in tags), str(path)], capture_output=True, text=True,
                         check=True, timeout=60).stdout
    return json.loads(out)[0]


def exiftool_write(path, *assignments: str) -> None:
    """exiftool writes ``assignments`` (``-Tag=value``; ``-Tag#=value`` for a number as stored) into ``path``."""
    subprocess.run([EXIFTOOL, "-q", "-overwrite_original", *assignments, str(path)], check=True, timeout=60,
                   capture_output=True)


def photo(path, w: int, h: int, *assignments: str):
    """A ``w`` x ``h`` (as stored) JPEG of a ramp, made by OpenCV, its EXIF written by exiftool."""
    import cv2

    codes = np.zeros((h, w, 3), np.uint8)
    codes[..., 1] = np.round(np.linspace(0, 255, w))[None, :]
    codes[..., 2] = np.round(np.linspace(0, 255, h))[:, None]
    assert cv2.imwrite(str(path), codes)
    if assignments:
        exiftool_write(path, *assignments)
    return path


def shown_fov(tags: dict, w: int, h: int) -> float:
    """exiftool's FOV (degrees across the 36 mm side of the 35 mm frame, its pi put right) as the field across the
    width of a ``w`` x ``h`` image whose diagonal sees what the 35 mm frame's does (CIPA DC-008's equivalent)."""
    across_36 = math.radians(float(tags["FOV"]) * EXIFTOOL_PI / math.pi)
    half = math.tan(across_36 / 2) * math.hypot(36.0, 24.0) / 36.0 * w / math.hypot(w, h)
    return math.degrees(2 * math.atan(half))


def run(capsys, *args: str) -> tuple[int, str]:
    """(exit code, stderr) of ``lenslab ARGS`` run in this process."""
    from lenslab.cli.main import main

    capsys.readouterr()
    code = main([str(a) for a in args])
    return code, capsys.readouterr().err


def from_exif_fov(capsys, path, tmp_path) -> float:
    """The field of view ``lenslab warp PATH --from exif`` takes, from its note (12 significant digits)."""
    code, err = run(capsys, "warp", path, "-o", tmp_path / "view.exr", "--from", "exif", "--to", "equirect",
                    "--size", "16x8", "--overwrite")
    assert code == 0, err
    return float(re.search(r"source lens from the file's EXIF: perspective:fov=([0-9.e+-]+)", err).group(1))


def oiio_attribute(path, name: str):
    """OpenImageIO's reading of attribute ``name`` of the image at ``path``."""
    oiio = pytest.importorskip("OpenImageIO")
    inp = oiio.ImageInput.open(str(path))
    assert inp is not None, oiio.geterror()
    try:
        return inp.spec().getattribute(name)
    finally:
        inp.close()


def tags_of_output(path) -> dict:
    """Model, FocalLengthIn35mmFilm, Orientation and frame of an output: exiftool's for JPEG, TIFF and PNG,
    OpenImageIO's for EXR (under its names)."""
    if str(path).endswith(".exr"):
        names = {"Model": "Model", "FocalLengthIn35mmFormat": "Exif:FocalLengthIn35mmFilm",
                 "Orientation": "Orientation", "ExifImageWidth": "Exif:PixelXDimension",
                 "ExifImageHeight": "Exif:PixelYDimension", "FocalPlaneXResolution": "Exif:FocalPlaneXResolution",
                 "FocalPlaneYResolution": "Exif:FocalPlaneYResolution"}
        return {k: v for k, n in names.items() if (v := oiio_attribute(path, n)) is not None}
    return exiftool(path, "Model", "FocalLengthIn35mmFormat", "Orientation", "ExifImageWidth", "ExifImageHeight",
                    "FocalPlaneXResolution", "FocalPlaneYResolution", "ImageWidth", "ImageHeight")


def recorded_frame(tags: dict, path) -> tuple[int, int]:
    """The frame an output's EXIF records: PixelXDimension x PixelYDimension, which Exif gives compressed images
    only; a TIFF's is its own ImageWidth x ImageLength (and it must not hold the others)."""
    if str(path).endswith(".tif"):
        assert "ExifImageWidth" not in tags and "ExifImageHeight" not in tags, tags
        return tags["ImageWidth"], tags["ImageHeight"]
    return tags["ExifImageWidth"], tags["ExifImageHeight"]
