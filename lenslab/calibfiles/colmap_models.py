"""Every camera model of COLMAP (and pycolmap 4.x) as a lenslab lens, both ways.

COLMAP puts the top-left pixel's centre at ``(0.5, 0.5)`` (``src/colmap/sensor/models.h``), as lenslab
does, so a perspective model's principal point is OpenCV's plus 0.5: ``cx = cx_colmap - 0.5`` on reading
(lenslab's calibrated models take OpenCV's numbers), ``+ 0.5`` on writing. ``EQUIRECTANGULAR`` has no
intrinsics: its two numbers are the image's width and height, and its pixel is lenslab's full-sphere
``equirect`` pixel as it is.
"""

from __future__ import annotations

from lenslab.errors import LensError, clip

#: COLMAP model -> (lenslab model, parameter names in COLMAP's order; f means fx = fy)
MODELS = {
    "SIMPLE_PINHOLE": ("opencv", "f cx cy"),
    "PINHOLE": ("opencv", "fx fy cx cy"),
    "SIMPLE_RADIAL": ("opencv", "f cx cy k1"),
    "RADIAL": ("opencv", "f cx cy k1 k2"),
    "OPENCV": ("opencv", "fx fy cx cy k1 k2 p1 p2"),
    "FULL_OPENCV": ("opencv", "fx fy cx cy k1 k2 p1 p2 k3 k4 k5 k6"),
    "SIMPLE_FISHEYE": ("kannala-brandt", "f cx cy"),
    "FISHEYE": ("kannala-brandt", "fx fy cx cy"),
    "SIMPLE_RADIAL_FISHEYE": ("kannala-brandt", "f cx cy k1"),
    "RADIAL_FISHEYE": ("kannala-brandt", "f cx cy k1 k2"),
    "OPENCV_FISHEYE": ("kannala-brandt", "fx fy cx cy k1 k2 k3 k4"),
    "THIN_PRISM_FISHEYE": ("kannala-brandt", "fx fy cx cy k1 k2 p1 p2 k3 k4 s1 s3"),
    "RAD_TAN_THIN_PRISM_FISHEYE": ("fisheye624", "fx fy cx cy k0 k1 k2 k3 k4 k5 p0 p1 s0 s1 s2 s3"),
    "FOV": ("devernay-fov", "fx fy cx cy omega"),
    "SIMPLE_DIVISION": ("division", "f cx cy k"),
    "DIVISION": ("division", "fx fy cx cy k"),
    "EUCM": ("eucm", "fx fy cx cy alpha beta"),
    "EQUIRECTANGULAR": ("equirect", "w h"),
}
#: lenslab models written under another model's name
ALIASES = {"opencv-fisheye": "kannala-brandt"}


def lens_values(model: str, width: int, height: int, nums: list[float]) -> dict:
    """The lenslab spec (a dict for ``make_lens``) of one COLMAP camera; ValueError names what is wrong."""
    if model not in MODELS:
        raise ValueError(f"unknown camera model {clip(model)}; valid: {', '.join(MODELS)}")
    name, keys = MODELS[model]
    keys = keys.split()
    if len(nums) != len(keys):
        raise ValueError(f"{model} takes {len(keys)} parameters ({', '.join(keys)}), got {len(nums)}")
    values = dict(zip(keys, nums))
    if model == "EQUIRECTANGULAR":
        if (values["w"], values["h"]) != (width, height):
            raise ValueError(f"EQUIRECTANGULAR's w, h ({values['w']:g}, {values['h']:g}) must be the image's "
                             f"size ({width}, {height}): lenslab reads full-sphere panoramas")
        return {"model": name}
    if "f" in values:
        values["fx"] = values["fy"] = values.pop("f")
    values["cx"] -= 0.5  # COLMAP's pixel centres are at +0.5
    values["cy"] -= 0.5
    return {"model": name, **values, "width": width, "height": height}


def colmap_model(lens) -> tuple[str, list[float]]:
    """The smallest COLMAP model that holds ``lens`` exactly, and its parameters."""
    kind = ALIASES.get(lens.name, lens.name)
    known = sorted({n for n, _ in MODELS.values()})
    if kind not in known:
        raise LensError(f"COLMAP has no {lens.name} model (it has {', '.join(known)}); write OpenCV or Kalibr "
                        "YAML, or lenslab TOML")
    v = dict(lens.param_values())
    if kind == "equirect":
        if any(v[p.name] != p.default for p in lens.params):
            raise LensError("COLMAP's EQUIRECTANGULAR is the full sphere; this equirect crops it "
                            "(lon_min, lon_max, lat_min, lat_max): write lenslab TOML")
        return "EQUIRECTANGULAR", [float(lens.width), float(lens.height)]
    v["cx"] += 0.5
    v["cy"] += 0.5
    candidates = sorted((len(keys.split()), model) for model, (name, keys) in MODELS.items() if name == kind)
    for _, model in candidates:
        keys = MODELS[model][1].split()
        held = set(keys) | ({"fx", "fy"} if "f" in keys else set())
        if "f" in keys and v["fx"] != v["fy"]:
            continue
        if not [k for k, p in v.items() if k not in held and k not in ("width", "height") and p]:
            return model, [v["fx"] if k == "f" else v[k] for k in keys]
    raise LensError(f"COLMAP has no model with every term of this {lens.name} camera (s2 and s4 of a fisheye, "
                    "or thin prism on a pinhole); write OpenCV YAML or lenslab TOML")
