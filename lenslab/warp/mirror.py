"""Mirrored views and mirrored sources (ffmpeg v360's ``h_flip``/``v_flip``/``d_flip`` and
``ih_flip``/``iv_flip``).

- A mirrored *view* reflects every output ray in the source's camera frame after the turn of the pose:
  ``h`` negates x (right), ``v`` negates y (up), ``d`` negates z (forward). :func:`mirror_source_pose` folds
  the reflection into the source camera's pose, so that the engine's one rotation between the cameras
  carries it (a reflection is orthonormal, like a rotation).
- A mirrored *source* is an image stored mirrored left to right (``h``) or top to bottom (``v``): the
  whole frame (cube faces and dual-fisheye halves change places too, as v360 reads them) or, for a
  stereo frame, each eye (its pieces that carry an ``eye``): :func:`mirror_frames` mirrors it back.
"""

from __future__ import annotations

import numpy as np

from lenslab.errors import WarpError

AXES = {"h": 0, "v": 1, "d": 2}


def parse_flips(text: str | None, allowed: str = "hvd", what: str = "--flip") -> str:
    """``"h,v"`` (or ``"hv"``) -> ``"hv"``; letters outside ``allowed`` are a WarpError."""
    if not text:
        return ""
    letters = [c for c in text.lower() if c not in ", "]
    bad = sorted(set(letters) - set(allowed))
    if bad or not letters:
        names = {"h": "h (left-right)", "v": "v (up-down)", "d": "d (front-back)"}
        raise WarpError(f"{what} {text!r}: give any of " + ", ".join(names[c] for c in allowed))
    return "".join(c for c in allowed if c in letters)


def mirror_matrix(flips: str) -> np.ndarray:
    """The reflection ``diag(+-1, +-1, +-1)`` of the axes named in ``flips`` (float64 3x3)."""
    m = np.ones(3)
    for c in flips:
        m[AXES[c]] = -1.0
    return np.diag(m)


def mirror_source_pose(src_camera, flips: str):
    """The source camera whose pose reflects the rays named in ``flips`` in its own frame: a ray the
    output sends along ``d`` (in the world) is read from the source along ``M R_src^T d``."""
    from lenslab.lenses import Camera, Pose

    if not flips:
        return src_camera
    pose = src_camera.pose
    return Camera(src_camera.lens, Pose(pose.rotation @ mirror_matrix(flips), pose.eye))


def mirror_frames(image: np.ndarray, lens, flips: str) -> np.ndarray:
    """``image`` mirrored left-right (``h`` in ``flips``) and/or top-bottom (``v``), as a new array: the
    whole frame, or each eye of a stereo frame (the lens's pieces that carry an ``eye``)."""
    if not flips:
        return image
    out = np.array(image, copy=True)
    eyes = [p for p in lens.pieces() if p.eye is not None]
    rects = [(p.x0, p.y0, p.width, p.height) for p in eyes] or [(0, 0, image.shape[1], image.shape[0])]
    for x0, y0, w, h in rects:
        sl = (slice(int(y0), int(y0 + h)), slice(int(x0), int(x0 + w)))
        frame = out[sl]
        if "h" in flips:
            frame = frame[:, ::-1]
        if "v" in flips:
            frame = frame[::-1]
        out[sl] = frame.copy()
    return out


__all__ = ["parse_flips", "mirror_matrix", "mirror_source_pose", "mirror_frames"]
