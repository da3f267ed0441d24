"""OpenCV FileStorage (YAML, JSON or XML) as ``cv2.FileStorage`` writes it.

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

from pathlib import Path

import numpy as np

from lenslab.calibfiles import CameraFileError
from lenslab.errors import LensError

OPENCV_KEYS = "k1 k2 p1 p2 k3 k4 k5 k6 s1 s2 s3 s4".split()


def sniff(path: Path, text: str) -> bool:
    head = text.lstrip()[:200]
    return head.startswith("%YAML") or head.startswith("<?xml") or ("camera_matrix" in text and "cam0" not in text)


def _fs(path: Path):
    import cv2

    try:
        fs = cv2.FileStorage(str(path), cv2.FILE_STORAGE_READ)
    except cv2.error as exc:
        raise CameraFileError(f"{path}: cv2.FileStorage cannot read it: {str(exc).strip().splitlines()[-1]}") from None
    if not fs.isOpened():
        raise CameraFileError(f"{path}: cv2.FileStorage cannot read it")
    return fs


def _number(path, fs, key, required=True):
    node = fs.getNode(key)
    if node.empty():
        if required:
            raise CameraFileError(f"{path}: missing key {key!r}")
        return None
    if node.isString():
        text = node.string().strip().lower()
        return text
    if node.isMap() or node.isSeq():
        m = node.mat()
        if m is None or m.size != 1:
            raise CameraFileError(f"{path}: key {key!r} must be one number")
        return float(m.ravel()[0])
    return float(node.real())


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
            raise CameraFileError(f"{path}: unknown {key} {value!r}; valid: {', '.join(FISHEYE_WORDS[:3])} (a fisheye), "
                                  f"{', '.join(PINHOLE_WORDS[:4])} (a pinhole)")
    if len(set(kinds.values())) > 1:
        raise CameraFileError(f"{path}: the keys disagree on the model: "
                              + ", ".join(f"{k} says {v}" for k, v in kinds.items()))
    return next(iter(kinds.values()), None)


def read(path: Path, text: str):
    from lenslab.lenses import make_lens

    fs = _fs(path)
    try:
        K = fs.getNode("camera_matrix").mat()
        if K is None:
            raise CameraFileError(f"{path}: missing key 'camera_matrix'")
        if K.shape != (3, 3):
            raise CameraFileError(f"{path}: key 'camera_matrix' must be a 3x3 matrix, got shape {K.shape}")
        D = fs.getNode("distortion_coefficients").mat()
        if D is None:
            raise CameraFileError(f"{path}: missing key 'distortion_coefficients'")
        D = D.ravel().astype(float)
        w = _number(path, fs, "image_width")
        h = _number(path, fs, "image_height")
        xi = _number(path, fs, "xi", required=False)
        said = {key: _number(path, fs, key, required=False) for key in MODEL_KEYS}
    finally:
        fs.release()
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
    K = np.array([[v["fx"], v.get("s", 0.0), v["cx"]], [0.0, v["fy"], v["cy"]], [0.0, 0.0, 1.0]])
    extra = {}
    if lens.name == "opencv":
        D = np.array([v[k] for k in OPENCV_KEYS])
        n = 12 if D[8:].any() else 8 if D[5:8].any() else 5 if D[4] else 4
        D = D[:n]
    elif lens.name in ("kannala-brandt", "opencv-fisheye"):
        if any(v[k] for k in "p1 p2 s1 s2 s3 s4".split()):
            raise LensError(f"{path}: OpenCV's fisheye model has no tangential or thin-prism terms; "
                            "write this camera as COLMAP cameras.txt or lenslab TOML")
        D = np.array([v[k] for k in "k1 k2 k3 k4".split()])
        extra["fisheye_model"] = 1
    elif lens.name == "omnidir":
        D = np.array([v[k] for k in "k1 k2 p1 p2".split()])
        extra["xi"] = v["xi"]
    else:
        raise LensError(f"{path}: OpenCV has no {lens.name} model; write it as Kalibr YAML (--format kalibr) "
                        "or lenslab TOML")
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
