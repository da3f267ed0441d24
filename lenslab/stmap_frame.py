"""Which frame of a photo an ST map addresses: the photo as shown (its EXIF orientation applied, as lenslab reads
a JPEG) or as stored (the camera sensor's pixels, the frame a calibration and a map made from it describe).

A map made by ``lenslab stmap`` records the source size it addresses in its ``lenslab:stmap`` mark (``from SPEC
WxH to ...``). A photo turned by its orientation (5 to 8: a quarter turn, so its width and height swap) is warped
in its stored frame when that size fits the stored frame and not the shown one; when it fits neither, the warp is
refused (it would stretch the image). A size fits a frame of the same shape: the same size, or one scaled alike
in width and height to within a pixel (an ST map holds fractions of its source's size, so a map of a plate
applies to the plate's proxy too). A map made by another tool records nothing: its own size (an undistortion's
map has its plate's size) stands in for the source's, only to choose between the two frames of a turned photo;
nothing is refused for it. Orientations 2 to 4 (mirrors, a half turn) keep the sizes, so they cannot tell the
frames apart: the map is applied to the photo as shown, and a note says so.
"""

from __future__ import annotations

import warnings

import numpy as np

from lenslab.errors import WarpError


def fits(size: tuple[int, int], frame: tuple[int, int]) -> bool:
    """Whether a map made for a source of ``size`` (W, H) addresses an image of ``frame`` (w, h) without
    stretching it: the same size, or ``size`` scaled alike in both directions to within a pixel."""
    (sw, sh), (w, h) = size, frame
    return (sw, sh) == (w, h) or (abs(sh * w / sw - h) <= 1.0 and abs(sw * h / sh - w) <= 1.0)


def frame_for_map(image: np.ndarray, meta: dict, map_size: tuple[int, int], recorded: tuple[int, int] | None,
                  src: str, map_path: str) -> np.ndarray:
    """``image`` (``H x W x C`` as read, turned as its EXIF orientation says) in the frame the ST map at
    ``map_path`` addresses: as shown, or as stored (a view, not a copy). ``map_size`` is the map's own (w, h),
    ``recorded`` the source size its mark records (None: none). Raises :class:`~lenslab.errors.WarpError` naming
    both sizes where ``recorded`` fits neither frame."""
    orientation = meta.get("exif_orientation", 1)
    shown = (image.shape[1], image.shape[0])
    stored = shown[::-1] if orientation in (5, 6, 7, 8) else shown
    size = recorded or map_size
    if recorded is not None and not fits(recorded, shown) and not fits(recorded, stored):
        as_stored = f" ({stored[0]}x{stored[1]} as stored, EXIF orientation {orientation})" if stored != shown else ""
        raise WarpError(f"{src}: the ST map {map_path} is made for a {recorded[0]}x{recorded[1]} source (its "
                        f"lenslab:stmap mark) and this image is {shown[0]}x{shown[1]}{as_stored}: it would be "
                        f"stretched; make the map for this image (lenslab stmap --source-size "
                        f"{shown[0]}x{shown[1]})")
    if stored != shown and fits(size, stored) and not fits(size, shown):
        from lenslab.io.exif_orientation import turn

        return turn(image, {6: 8, 8: 6}.get(orientation, orientation))  # the inverse turn: the stored frame
    if orientation != 1 and fits(size, stored) and fits(size, shown):
        warnings.warn(f"it is shown {_turned(orientation)} (EXIF orientation {orientation}); the ST map's "
                      f"source size {size[0]}x{size[1]} fits it both as stored and as shown, so the map is applied "
                      "to it as shown", UserWarning, stacklevel=2)
    return image


def _turned(orientation: int) -> str:
    from lenslab.io.exif_orientation import TURNS

    return TURNS[orientation].replace("turned ", "turned by ")


__all__ = ["fits", "frame_for_map"]
