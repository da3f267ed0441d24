"""COLMAP ``cameras.txt``: ``CAMERA_ID MODEL WIDTH HEIGHT PARAMS[]``, one camera a line, ``#`` comments.

Every COLMAP model is read and written (:mod:`lenslab.calibfiles.colmap_models` holds the table and the
pixel-centre conversion).
"""

from __future__ import annotations

import math
from pathlib import Path

from lenslab.calibfiles import CameraFileError
from lenslab.calibfiles.colmap_models import MODELS, colmap_model, lens_values  # noqa: F401
from lenslab.errors import LensError
from lenslab.lenses.core.base import MAX_SIDE


def sniff(path: Path, text: str) -> bool:
    for line in text.splitlines():
        parts = line.split()
        if parts and not parts[0].startswith("#"):
            return len(parts) >= 4 and parts[0].isdigit() and parts[1].isupper()
    return "# Camera list" in text


def read(path: Path, text: str):
    from lenslab.lenses import make_lens

    cams = []
    for n, line in enumerate(text.splitlines(), 1):
        parts = line.split()
        if not parts or parts[0].startswith("#"):
            continue
        where = f"{path}: line {n}"
        if len(parts) < 4:
            raise CameraFileError(f"{where}: expected CAMERA_ID MODEL WIDTH HEIGHT PARAMS...")
        cid, model = parts[0][:24], parts[1]
        try:
            w, h = int(parts[2]), int(parts[3])
            nums = [float(p) for p in parts[4:]]
        except ValueError:
            raise CameraFileError(f"{where}: WIDTH, HEIGHT and the parameters must be numbers") from None
        if not all(math.isfinite(v) for v in nums) or not (1 <= w <= MAX_SIDE and 1 <= h <= MAX_SIDE):
            raise CameraFileError(f"{where}: WIDTH and HEIGHT must be in 1..{MAX_SIDE} and the parameters finite")
        try:
            values = lens_values(model, w, h, nums)
        except ValueError as exc:
            raise CameraFileError(f"{where}: {exc}") from None
        try:
            cams.append((cid, make_lens(values, (w, h))))
        except LensError as exc:  # a bad value in the file
            raise CameraFileError(f"{where}: {exc}") from None
    if not cams:
        raise CameraFileError(f"{path}: no camera line (CAMERA_ID MODEL WIDTH HEIGHT PARAMS...)")
    return cams


def write(path: Path, lens) -> None:
    model, params = colmap_model(lens)
    text = ("# Camera list with one line of data per camera:\n"
            "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
            "# Number of cameras: 1\n"
            f"1 {model} {lens.width} {lens.height} " + " ".join(repr(float(p)) for p in params) + "\n")
    Path(path).write_text(text, encoding="utf-8")
