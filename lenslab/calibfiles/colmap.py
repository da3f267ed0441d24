"""COLMAP ``cameras.txt``: ``CAMERA_ID MODEL WIDTH HEIGHT PARAMS[]``, one camera a line, ``#`` comments.

COLMAP puts the top-left pixel's centre at ``(0.5, 0.5)`` (its ``models.h``), as lenslab does, so its
principal point is OpenCV's plus 0.5: ``cx = cx_colmap - 0.5`` on reading, ``+ 0.5`` on writing.
"""

from __future__ import annotations

import math
from pathlib import Path

from lenslab.calibfiles import CameraFileError
from lenslab.errors import LensError, clip
from lenslab.lenses.base import MAX_SIDE

#: COLMAP model -> (lenslab model, parameter names in COLMAP's order; f means fx = fy)
MODELS = {
    "SIMPLE_PINHOLE": ("opencv", "f cx cy"),
    "PINHOLE": ("opencv", "fx fy cx cy"),
    "SIMPLE_RADIAL": ("opencv", "f cx cy k1"),
    "RADIAL": ("opencv", "f cx cy k1 k2"),
    "OPENCV": ("opencv", "fx fy cx cy k1 k2 p1 p2"),
    "FULL_OPENCV": ("opencv", "fx fy cx cy k1 k2 p1 p2 k3 k4 k5 k6"),
    "OPENCV_FISHEYE": ("kannala-brandt", "fx fy cx cy k1 k2 k3 k4"),
    "SIMPLE_RADIAL_FISHEYE": ("kannala-brandt", "f cx cy k1"),
    "RADIAL_FISHEYE": ("kannala-brandt", "f cx cy k1 k2"),
    "THIN_PRISM_FISHEYE": ("kannala-brandt", "fx fy cx cy k1 k2 p1 p2 k3 k4 s1 s3"),
    "FOV": ("devernay-fov", "fx fy cx cy omega"),
}


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
        if model not in MODELS:
            raise CameraFileError(f"{where}: unknown camera model {clip(model)}; valid: {', '.join(MODELS)}")
        name, keys = MODELS[model]
        keys = keys.split()
        try:
            w, h = int(parts[2]), int(parts[3])
            nums = [float(p) for p in parts[4:]]
        except ValueError:
            raise CameraFileError(f"{where}: WIDTH, HEIGHT and the parameters must be numbers") from None
        if not all(math.isfinite(v) for v in nums) or not (1 <= w <= MAX_SIDE and 1 <= h <= MAX_SIDE):
            raise CameraFileError(f"{where}: WIDTH and HEIGHT must be in 1..{MAX_SIDE} and the parameters finite")
        if len(nums) != len(keys):
            raise CameraFileError(f"{where}: {model} takes {len(keys)} parameters ({', '.join(keys)}), got {len(nums)}")
        values = dict(zip(keys, nums))
        if "f" in values:
            values["fx"] = values["fy"] = values.pop("f")
        values["cx"] -= 0.5  # COLMAP's pixel centres are at +0.5
        values["cy"] -= 0.5
        try:
            cams.append((cid, make_lens({"model": name, **values, "width": w, "height": h}, (w, h))))
        except LensError as exc:  # a bad value in the file
            raise CameraFileError(f"{where}: {exc}") from None
    if not cams:
        raise CameraFileError(f"{path}: no camera line (CAMERA_ID MODEL WIDTH HEIGHT PARAMS...)")
    return cams


def colmap_model(lens) -> tuple[str, list[float]]:
    """The smallest COLMAP model that holds ``lens`` exactly, and its parameters."""
    v = dict(lens.param_values())
    if lens.name not in ("opencv", "kannala-brandt", "opencv-fisheye", "devernay-fov"):
        raise LensError(f"COLMAP has no {lens.name} model; write OpenCV or Kalibr YAML, or lenslab TOML")
    v["cx"] += 0.5
    v["cy"] += 0.5
    kind = "kannala-brandt" if lens.name == "opencv-fisheye" else lens.name
    for model, (name, keys) in MODELS.items():
        if name != kind or model.startswith("SIMPLE_RADIAL_FISHEYE") or model == "RADIAL_FISHEYE":
            continue
        keys = keys.split()
        held = set(keys) | ({"fx", "fy"} if "f" in keys else set())
        if "f" in keys and v["fx"] != v["fy"]:
            continue
        zero = [k for k, p in v.items() if k not in held and k not in ("width", "height") and p]
        if not zero:
            return model, [v["fx"] if k == "f" else v[k] for k in keys]
    raise LensError(f"COLMAP has no model with every term of this {lens.name} camera (s2 and s4 of a fisheye, "
                    "or thin prism on a pinhole); write OpenCV YAML or lenslab TOML")


def write(path: Path, lens) -> None:
    model, params = colmap_model(lens)
    text = ("# Camera list with one line of data per camera:\n"
            "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
            "# Number of cameras: 1\n"
            f"1 {model} {lens.width} {lens.height} " + " ".join(repr(float(p)) for p in params) + "\n")
    Path(path).write_text(text, encoding="utf-8")
