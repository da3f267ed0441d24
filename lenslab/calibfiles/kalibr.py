"""Kalibr camchain YAML: ``cam0``, ``cam1``... each with ``camera_model``, ``intrinsics``,
``distortion_model``, ``distortion_coeffs`` and ``resolution``.

Models: ``pinhole`` ``[fu, fv, pu, pv]``, ``omni`` ``[xi, fu, fv, pu, pv]``, ``ds``
``[xi, alpha, fu, fv, pu, pv]``, ``eucm`` ``[alpha, beta, fu, fv, pu, pv]``; distortions ``radtan``
``[k1, k2, r1, r2]``, ``equidistant`` ``[k1, k2, k3, k4]`` (pinhole only) and ``none``. Kalibr puts pixel
centres at integers, as OpenCV does: numbers verbatim.
"""

from __future__ import annotations

import math
from pathlib import Path

from lenslab.calibfiles import CameraFileError
from lenslab.errors import LensError, clip
from lenslab.lenses.core.base import MAX_SIDE

INTRINSICS = {
    "pinhole": "fx fy cx cy", "omni": "xi fx fy cx cy",
    "ds": "xi alpha fx fy cx cy", "eucm": "alpha beta fx fy cx cy",
}
DISTORTIONS = {"radtan": "k1 k2 p1 p2", "equidistant": "k1 k2 k3 k4", "none": ""}
REQUIRED = ("camera_model", "intrinsics", "distortion_model", "distortion_coeffs", "resolution")


def sniff(path: Path, text: str) -> bool:
    return "camera_model" in text and "intrinsics" in text


def _load(path: Path, text: str) -> dict:
    from lenslab.inputs.safeload import load_yaml

    data = load_yaml(text, path, CameraFileError)
    if not isinstance(data, dict):
        raise CameraFileError(f"{path}: a Kalibr camchain holds cam0, cam1, ... tables")
    return data


def _lens_of(path: Path, cid: str, cam) -> object:
    from lenslab.lenses import make_lens

    cid = clip(cid, 24).strip("'")
    if not isinstance(cam, dict):
        raise CameraFileError(f"{path}: {cid} must be a table")
    for key in REQUIRED:
        if key not in cam:
            if key in ("distortion_model", "distortion_coeffs") and cam.get("camera_model") in ("ds", "eucm"):
                continue
            raise CameraFileError(f"{path}: {cid}: missing key {key!r}")
    model = cam["camera_model"]
    dist = cam.get("distortion_model", "none")
    if not isinstance(model, str) or model not in INTRINSICS:
        raise CameraFileError(f"{path}: {cid}: unknown camera_model {clip(model)}; valid: {', '.join(INTRINSICS)}")
    if not isinstance(dist, str) or dist not in DISTORTIONS:
        raise CameraFileError(f"{path}: {cid}: unknown distortion_model {clip(dist)}; valid: "
                              f"{', '.join(DISTORTIONS)}")
    names = INTRINSICS[model].split()
    dnames = DISTORTIONS[dist].split()
    intr = _numbers(path, cid, "intrinsics", cam["intrinsics"], len(names))
    coeffs = _numbers(path, cid, "distortion_coeffs", cam.get("distortion_coeffs", []), len(dnames))
    res = _numbers(path, cid, "resolution", cam["resolution"], 2)
    values = dict(zip(names, intr)) | dict(zip(dnames, coeffs))
    if model == "pinhole":
        name = "kannala-brandt" if dist == "equidistant" else "opencv"
    elif model == "omni":
        if dist == "equidistant":
            raise CameraFileError(f"{path}: {cid}: distortion_model 'equidistant' goes with camera_model 'pinhole' only")
        name = "omnidir"
    else:
        if dist != "none":
            raise CameraFileError(f"{path}: {cid}: camera_model {model!r} takes distortion_model 'none', got {dist!r}")
        name = {"ds": "double-sphere", "eucm": "eucm"}[model]
    if not all(v == int(v) and 1 <= v <= MAX_SIDE for v in res):
        raise CameraFileError(f"{path}: {cid}: key 'resolution' must be two whole numbers of pixels in 1..{MAX_SIDE}")
    w, h = int(res[0]), int(res[1])
    try:
        return make_lens({"model": name, **values, "width": w, "height": h}, (w, h))
    except LensError as exc:  # a bad value in the file
        raise CameraFileError(f"{path}: {cid}: {exc}") from None


def _numbers(path, cid, key, value, n):
    if not isinstance(value, list):
        raise CameraFileError(f"{path}: {cid}: key {key!r} must be a list of numbers, got {clip(value)}")
    if len(value) != n:
        raise CameraFileError(f"{path}: {cid}: key {key!r} needs {n} numbers, got {len(value)}")
    try:
        out = [float(v) for v in value if not isinstance(v, (bool, dict, list))]
    except (TypeError, ValueError, OverflowError):
        out = []
    if len(out) != n or not all(math.isfinite(v) for v in out):
        raise CameraFileError(f"{path}: {cid}: key {key!r} must be a list of {n} finite numbers")
    return out


def read(path: Path, text: str):
    data = _load(path, text)
    cams = [(k, v) for k, v in data.items() if str(k).startswith("cam")]
    if not cams:
        raise CameraFileError(f"{path}: missing key 'cam0' (a Kalibr camchain holds cam0, cam1, ...)")
    return [(str(k), _lens_of(path, str(k), v)) for k, v in cams]


def write(path: Path, lens) -> None:
    import yaml

    v = lens.param_values()
    kb = lens.name in ("kannala-brandt", "opencv-fisheye")
    if lens.name == "opencv" or kb:
        extra = "p1 p2 s1 s2 s3 s4" if kb else "k3 k4 k5 k6 s1 s2 s3 s4"
        if any(v[k] for k in extra.split()):
            raise LensError(f"Kalibr's pinhole {'equidistant' if kb else 'radtan'} model has no "
                            f"{', '.join(k for k in extra.split() if v[k])}; write OpenCV YAML or lenslab TOML")
        model, dist = "pinhole", ("equidistant" if kb else "radtan")
    elif lens.name == "omnidir":
        if v["s"]:
            raise LensError(f"Kalibr's omni model has no skew; write OpenCV YAML or lenslab TOML")
        model, dist = "omni", "radtan"
    elif lens.name in ("double-sphere", "eucm"):
        model, dist = ("ds" if lens.name == "double-sphere" else "eucm"), "none"
    else:
        raise LensError(f"Kalibr has no {lens.name} model; write lenslab TOML")
    cam = {
        "camera_model": model,
        "intrinsics": [float(v[k]) for k in INTRINSICS[model].split()],
        "distortion_model": dist,
        "distortion_coeffs": [float(v[k]) for k in DISTORTIONS[dist].split()],
        "resolution": [int(lens.width), int(lens.height)],
    }
    Path(path).write_text(yaml.safe_dump({"cam0": cam}, sort_keys=False), encoding="utf-8")
