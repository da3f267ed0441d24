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
from lenslab.lenses.core.pose import mirror_matrix

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


def mirror_source_pose(src_camera, flips: str):
    """The source camera whose pose reflects the rays named in ``flips`` in its own frame: a ray the
    output sends along ``d`` (in the world) is read from the source along ``M R_src^T d``."""
    from lenslab.lenses import Camera, Pose

    if not flips:
        return src_camera
    pose = src_camera.pose
    return Camera(src_camera.lens, Pose(pose.rotation @ mirror_matrix(flips), pose.eye))


def shown_camera(true_src, src, dst):
    """The camera whose rays the pixels of a warp from ``src`` (``true_src`` with its rays mirrored by
    :func:`mirror_source_pose`) into ``dst`` show, in ``true_src``'s world: a ray ``d`` of ``dst`` reads the source
    along ``R_true R_src^T d``, ``R_true M R_true^T d`` for the mirror ``M``. A mirrored view's pose has a determinant
    of -1 (a turn after a mirror, :attr:`lenslab.lenses.Pose.mirror`), which the output records, so that ``--to`` the
    output, ``tracer render`` of its camera and ``lenslab info`` see the view its pixels hold. ``dst`` itself when
    nothing was mirrored."""
    from lenslab.lenses import Camera, Pose

    if src.pose.rotation is true_src.pose.rotation or np.array_equal(src.pose.rotation, true_src.pose.rotation):
        return dst
    turn = true_src.pose.rotation @ src.pose.rotation.T @ dst.pose.rotation
    return Camera(dst.lens, Pose(turn, dst.pose.eye))


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


__all__ = ["parse_flips", "mirror_matrix", "mirror_source_pose", "shown_camera", "mirror_frames"]
