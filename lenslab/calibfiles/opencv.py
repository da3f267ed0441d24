"""OpenCV FileStorage (YAML, JSON or XML) as ``cv2.FileStorage`` writes it, read by lenslab's bounded
parsers (:mod:`lenslab.inputs.safeload`; ``cv2.FileStorage`` itself crashes on hostile files).

Keys: ``camera_matrix`` (3x3), ``distortion_coefficients`` (4, 5, 8, 12 or 14 numbers: OpenCV's
``k1 k2 p1 p2 [k3 [k4 k5 k6 [s1 s2 s3 s4]]]``), ``image_width``, ``image_height``; a fisheye
(Kannala-Brandt) says ``fisheye_model: 1`` as OpenCV's calibration sample writes it, or
``distortion_model`` or ``model`` set to ``equidistant`` (Kalibr's word), ``fisheye`` or ``kannala_brandt``,
and has ``k1..k4``; ``radtan``, ``plumb_bob``, ``rational_polynomial`` or ``pinhole`` say pinhole. Four
coefficients with no such key are read as the pinhole ``k1 k2 p1 p2`` with an
:class:`AmbiguousCalibrationWarning` that says how to choose the fisheye; ``xi`` makes it ``cv2.omnidir``
(``k1 k2 p1 p2``, skew in ``camera_matrix[0][1]``). Pixel centres at integers: numbers verbatim.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from lenslab.calibfiles import CameraFileError
from lenslab.errors import LensError, clip
from lenslab.lenses.core.base import MAX_SIDE

OPENCV_KEYS = "k1 k2 p1 p2 k3 k4 k5 k6 s1 s2 s3 s4".split()


def sniff(path: Path, text: str) -> bool:
    head = text.lstrip()[:200]
    return head.startswith("%YAML") or head.startswith("<?xml") or ("camera_matrix" in text and "cam0" not in text)


#: element types of an OpenCV matrix (its ``dt``)
_DT = {"u": "uint8", "c": "int8", "w": "uint16", "s": "int16", "i": "int32", "f": "float32", "d": "float64",
       "h": "float16"}
#: the largest matrix a camera file needs (the longest distortion vector has 14 numbers)
_MAX_ELEMENTS = 64


def _matrix(path, key, node):
    """An OpenCV matrix node (``rows``, ``cols``, ``dt``, ``data``) -> a float64 rows x cols array."""
    if not isinstance(node, dict):
        raise CameraFileError(f"{path}: key {key!r} must be a matrix (rows, cols, dt, data)")
    rows, cols, dt, data = (node.get(k) for k in ("rows", "cols", "dt", "data"))
    if not all(isinstance(v, int) and not isinstance(v, bool) for v in (rows, cols)):
        raise CameraFileError(f"{path}: key {key!r}: rows and cols must be integers, got {clip(rows)} and "
                              f"{clip(cols)}")
    if not (1 <= rows <= _MAX_ELEMENTS and 1 <= cols <= _MAX_ELEMENTS and rows * cols <= _MAX_ELEMENTS):
        raise CameraFileError(f"{path}: key {key!r} declares a {rows} x {cols} matrix; a camera file holds "
                              f"at most {_MAX_ELEMENTS} numbers in one")
    if not isinstance(dt, str) or dt.strip() not in _DT:
        raise CameraFileError(f"{path}: key {key!r}: dt {clip(dt)} is not a one-channel OpenCV type "
                              f"({', '.join(_DT)})")
    numbers = _floats(path, key, data.split() if isinstance(data, str) else data)
    if len(numbers) != rows * cols:
        raise CameraFileError(f"{path}: key {key!r} declares {rows} x {cols} = {rows * cols} numbers, its data "
                              f"holds {len(numbers)}")
    return np.array(numbers, float).reshape(rows, cols)


def _floats(path, key, values) -> list[float]:
    if not isinstance(values, (list, tuple)) or len(values) > _MAX_ELEMENTS:
        raise CameraFileError(f"{path}: key {key!r} must be a list of at most {_MAX_ELEMENTS} numbers")
    out = []
    for v in values:
        try:
            if isinstance(v, (bool, dict, list)):
                raise TypeError
            f = float(v)
        except (TypeError, ValueError, OverflowError):
            raise CameraFileError(f"{path}: key {key!r} holds {clip(v)}, not a number") from None
        if not math.isfinite(f):
            raise CameraFileError(f"{path}: key {key!r} holds {clip(v)}; every number must be finite")
        out.append(f)
    return out


def _opencv_matrix_tag(loader, node):
    return loader.construct_mapping(node, deep=True)


def _from_xml(path, root) -> dict:
    out = {}
    for el in root:
        if len(el):  # a matrix: rows, cols, dt, data children
            sub = {c.tag: (c.text or "").strip() for c in el}
            for k in ("rows", "cols"):
                try:
                    sub[k] = int(sub.get(k, ""))
                except ValueError:
                    sub[k] = None
            out[el.tag] = sub
        else:
            out[el.tag] = (el.text or "").strip()
    return out


def load_storage(path: Path, text: str) -> dict:
    """The top-level keys of an OpenCV FileStorage file (YAML, JSON or XML), parsed by lenslab's bounded
    parsers (never by ``cv2.FileStorage``, which crashes on hostile nesting and sizes)."""
    from lenslab.inputs.safeload import load_json, load_xml, load_yaml

    head = text.lstrip()
    if head.startswith("<"):
        root = load_xml(text, path, CameraFileError)
        data = _from_xml(path, root)
    elif head.startswith("{"):
        data = load_json(text, path, CameraFileError)
    else:
        if head.startswith("%YAML"):  # OpenCV writes '%YAML:1.0', which is not YAML 1.1's directive syntax
            head = head.partition("\n")[2]
        data = load_yaml(head, path, CameraFileError, tags={"tag:yaml.org,2002:opencv-matrix": _opencv_matrix_tag})
    if not isinstance(data, dict):
        raise CameraFileError(f"{path}: an OpenCV camera file is a map of keys (camera_matrix, ...)")
    return data


def _number(path, data, key, required=True):
    if key not in data:
        if required:
            raise CameraFileError(f"{path}: missing key {key!r}")
        return None
    value = data[key]
    if isinstance(value, str):
        try:
            value = float(value)
        except ValueError:
            return value.strip().lower()[:40]
    if isinstance(value, dict):
        m = _matrix(path, key, value)
        if m.size != 1:
            raise CameraFileError(f"{path}: key {key!r} must be one number")
        return float(m.ravel()[0])
    return _floats(path, key, [value])[0]


def _side(path, data, key) -> int:
    v = _number(path, data, key)
    if isinstance(v, str) or v != int(v) or not 1 <= v <= MAX_SIDE:
        raise CameraFileError(f"{path}: key {key!r} must be a whole number of pixels in 1..{MAX_SIDE}, got {clip(v)}")
    return int(v)


def _distortion(path, data) -> np.ndarray:
    if "distortion_coefficients" not in data:
        raise CameraFileError(f"{path}: missing key 'distortion_coefficients'")
    value = data["distortion_coefficients"]
    if isinstance(value, dict):
        return _matrix(path, "distortion_coefficients", value).ravel()
    return np.array(_floats(path, "distortion_coefficients", value), float)


#: the keys that say which model a file holds, and their words (OpenCV's sample, Kalibr, ROS, others)
MODEL_KEYS = ("fisheye_model", "distortion_model", "model")
FISHEYE_WORDS = ("equidistant", "fisheye", "kannala_brandt", "kannala-brandt", "kb4", "opencv_fisheye")
PINHOLE_WORDS = ("radtan", "plumb_bob", "rational_polynomial", "pinhole", "opencv", "brown", "brown_conrady")


class AmbiguousCalibrationWarning(UserWarning):
    """A calibration file could be read two ways; the message says which was taken and how to choose."""


def model_kind(path: Path, said: dict) -> str | None:
    """"fisheye", "pinhole", or None when no key says; a CameraFileError for a word no reader knows or
    keys that disagree."""
    kinds = {}
    for key, value in said.items():
        if value is None:
            continue
        if key == "fisheye_model" and not isinstance(value, str):
            kinds[key] = "fisheye" if value == 1 else "pinhole"
            continue
        word = str(value).strip().lower()
        if word in FISHEYE_WORDS:
            kinds[key] = "fisheye"
        elif word in PINHOLE_WORDS:
            kinds[key] = "pinhole"
        else:
            raise CameraFileError(f"{path}: unknown {key} {clip(value)}; valid: {', '.join(FISHEYE_WORDS[:3])} (a fisheye), "
                                  f"{', '.join(PINHOLE_WORDS[:4])} (a pinhole)")
    if len(set(kinds.values())) > 1:
        raise CameraFileError(f"{path}: the keys disagree on the model: "
                              + ", ".join(f"{k} says {v}" for k, v in kinds.items()))
    return next(iter(kinds.values()), None)


def read(path: Path, text: str):
    from lenslab.lenses import make_lens

    data = load_storage(path, text)
    if "camera_matrix" not in data:
        raise CameraFileError(f"{path}: missing key 'camera_matrix'")
    K = _matrix(path, "camera_matrix", data["camera_matrix"])
    if K.shape != (3, 3):
        raise CameraFileError(f"{path}: key 'camera_matrix' must be a 3x3 matrix, got shape {K.shape}")
    D = _distortion(path, data)
    w = _side(path, data, "image_width")
    h = _side(path, data, "image_height")
    xi = _number(path, data, "xi", required=False)
    if isinstance(xi, str):
        raise CameraFileError(f"{path}: key 'xi' must be a number, got {clip(xi)}")
    said = {key: _number(path, data, key, required=False) for key in MODEL_KEYS}
    kind = model_kind(path, said)
    values = {"fx": K[0, 0], "fy": K[1, 1], "cx": K[0, 2], "cy": K[1, 2], "width": int(w), "height": int(h)}
    if xi is not None:
        if D.size != 4:
            raise CameraFileError(f"{path}: key 'distortion_coefficients' of an omnidir camera (with xi) needs 4 numbers "
                            f"(k1 k2 p1 p2), got {D.size}")
        values.update(xi=xi, s=K[0, 1], **dict(zip("k1 k2 p1 p2".split(), D)))
        name = "omnidir"
    elif kind == "fisheye":
        if D.size != 4:
            raise CameraFileError(f"{path}: key 'distortion_coefficients' of a fisheye camera needs 4 numbers "
                            f"(k1 k2 k3 k4), got {D.size}")
        values.update(zip("k1 k2 k3 k4".split(), D))
        name = "kannala-brandt"
    else:
        if D.size not in (4, 5, 8, 12, 14):
            raise CameraFileError(f"{path}: key 'distortion_coefficients' needs 4, 5, 8, 12 or 14 numbers, got {D.size}")
        if D.size == 14 and D[12:].any():
            raise CameraFileError(f"{path}: key 'distortion_coefficients': the tilt terms tauX, tauY are not supported")
        values.update(zip(OPENCV_KEYS, D[:12]))
        name = "opencv"
        if kind is None and D.size == 4:
            import warnings

            warnings.warn(AmbiguousCalibrationWarning(
                f"{path}: 4 distortion coefficients and no fisheye_model or distortion_model key: read as "
                "OpenCV's pinhole model (k1 k2 p1 p2); if the camera is a fisheye (Kannala-Brandt, "
                "cv2.fisheye: k1 k2 k3 k4), add 'distortion_model: equidistant' (or 'fisheye_model: 1') to the "
                "file; 'distortion_model: plumb_bob' says pinhole and silences this note"), stacklevel=2)
    if name != "omnidir" and K[0, 1] != 0:
        raise CameraFileError(f"{path}: key 'camera_matrix' has a skew, which only the omnidir model (with xi) takes")
    try:
        lens = make_lens({"model": name, **{k: float(v) if k not in ("width", "height") else v
                                            for k, v in values.items()}}, (int(w), int(h)))
    except LensError as exc:  # a bad value in the file
        raise CameraFileError(f"{path}: {exc}") from None
    return [("0", lens)]


def write(path: Path, lens) -> None:
    import cv2

    v = lens.param_values()
    extra = {}
    if lens.name == "opencv":
        D = np.array([v[k] for k in OPENCV_KEYS])
        n = 12 if D[8:].any() else 8 if D[5:8].any() else 5 if D[4] else 4
        D = D[:n]
        if n == 4:  # four numbers are a fisheye's too: the file says which, as ROS does, and reads back without a note
            extra["distortion_model"] = "plumb_bob"
    elif lens.name in ("kannala-brandt", "opencv-fisheye"):
        if any(v[k] for k in "p1 p2 s1 s2 s3 s4".split()):
            raise LensError(f"OpenCV's fisheye model has no tangential or thin-prism terms; "
                            "write this camera as COLMAP cameras.txt or lenslab TOML")
        D = np.array([v[k] for k in "k1 k2 k3 k4".split()])
        extra["fisheye_model"] = 1
    elif lens.name == "omnidir":
        D = np.array([v[k] for k in "k1 k2 p1 p2".split()])
        extra["xi"] = v["xi"]
    else:
        raise LensError(f"OpenCV has no {lens.name} model; write it as Kalibr YAML (--format kalibr) "
                        "or lenslab TOML")
    K = np.array([[v["fx"], v.get("s", 0.0), v["cx"]], [0.0, v["fy"], v["cy"]], [0.0, 0.0, 1.0]])
    fs = cv2.FileStorage(str(path), cv2.FILE_STORAGE_WRITE)
    try:
        fs.write("image_width", int(lens.width))
        fs.write("image_height", int(lens.height))
        for k, val in extra.items():
            fs.write(k, val)
        fs.write("camera_matrix", K)
        fs.write("distortion_coefficients", D.reshape(-1, 1))
    finally:
        fs.release()
