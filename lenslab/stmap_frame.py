"""Which frame of a photo an ST map addresses: the photo as shown (its EXIF orientation applied, as lenslab reads
a JPEG) or as stored (the camera sensor's pixels, the frame a calibration and a map made from it describe).

A map made by ``lenslab stmap`` records the source size it addresses in its ``lenslab:stmap`` mark (``from SPEC
WxH to ...``). A photo turned by its orientation (5 to 8: a quarter turn, so its width and height swap) is warped
in its stored frame when that size fits the stored frame and not the shown one; when it fits neither, the warp is
refused (it would stretch the image). A size fits a frame of the same shape: the same size, or one scaled alike
in width and height to within a pixel (an ST map holds fractions of its source's size, so a map of a plate
applies to the plate's proxy too), or any size where the source lens reads the same directions at the same
fractions of its frame (an equirect, a cube map: a map made with ``--size 512x512`` and no ``--source-size`` for
an equirect source applies to a 2:1 panorama as it is). A map made by another tool records nothing: its own size
(an undistortion's map has its plate's size) stands in for the source's, only to choose between the two frames of a turned photo;
nothing is refused for it. Orientations 2 to 4 (mirrors, a half turn) keep the sizes, so they cannot tell the
frames apart: the map is applied to the photo as shown, and a note says so.
"""

from __future__ import annotations

import re
import warnings

import numpy as np

from lenslab.errors import WarpError

#: the mark ``lenslab stmap`` writes: ``from SPEC WxH to SPEC WxH`` (a spec may hold spaces: a lensfun lens's name)
MARK = re.compile(r"from (.+?) ([1-9]\d*)x([1-9]\d*) to (.+) (\d+)x(\d+)")
#: fractions per side at which a source lens's directions are compared in two frames (:func:`same_fractions`)
GRID = 17
#: directions closer than this (radians; a pixel of a 360-degree 8K frame is 7.7e-4) are the same
SAME_DIRECTION = 1e-6


def recorded_source(meta: dict) -> tuple[str, tuple[int, int]] | None:
    """The source lens spec and size ``(SPEC, (W, H))`` that the ``lenslab:stmap`` mark of a map's header records;
    None for a map without it (one made by another tool), or whose source has no pixels (a damaged header).

    >>> recorded_source({"attributes": {"lenslab:stmap": "from lensfun:lens=A B,focal=15 300x200 to equirect 64x32"}})
    ('lensfun:lens=A B,focal=15', (300, 200))
    """
    found = MARK.fullmatch(str((meta.get("attributes") or {}).get("lenslab:stmap", "")).strip())
    return (found[1], (int(found[2]), int(found[3]))) if found else None


def same_fractions(spec: str, size: tuple[int, int], frame: tuple[int, int]) -> bool:
    """Whether the lens ``spec`` sees the same directions at the same fractions of its frame at ``size`` (W, H) as at
    ``frame`` (w, h), on a grid of :data:`GRID` fractions a side: a map made for a source of ``size`` then applies to
    an image of ``frame`` unstretched (an equirect's, a cube map's fractions are directions whatever the shape; a
    fisheye's or a perspective view's are not). False for a spec that cannot be made at either size."""
    from lenslab.lenses.registry import make_lens

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # (a cube map off its layout's shape: its note is not this command's)
            lenses = [make_lens(spec, tuple(s)) for s in (size, frame)]
    except Exception:  # noqa: BLE001 - a lens that cannot be made so: the sizes alone decide
        return False
    f = (np.arange(GRID) + 0.5) / GRID
    uv = np.stack(np.meshgrid(f, f), -1).reshape(-1, 2)
    (a, seen_a), (b, seen_b) = (lens.pixel_to_dir(uv * (lens.width, lens.height)) for lens in lenses)
    return bool(seen_a.any() and (seen_a == seen_b).all()
                and (np.linalg.norm(a - b, axis=-1)[seen_a] <= SAME_DIRECTION).all())


def addresses(recorded: tuple[str, tuple[int, int]], frame: tuple[int, int]) -> bool:
    """Whether a map whose mark records ``recorded`` (:func:`recorded_source`) applies to an image of ``frame``."""
    spec, size = recorded
    return fits(size, frame) or same_fractions(spec, size, frame)


def fits(size: tuple[int, int], frame: tuple[int, int]) -> bool:
    """Whether a map made for a source of ``size`` (W, H) addresses an image of ``frame`` (w, h) without
    stretching it: the same size, or ``size`` scaled alike in both directions to within a pixel."""
    (sw, sh), (w, h) = size, frame
    return (sw, sh) == (w, h) or (abs(sh * w / sw - h) <= 1.0 and abs(sw * h / sh - w) <= 1.0)


def frame_for_map(image: np.ndarray, meta: dict, map_size: tuple[int, int],
                  recorded: tuple[str, tuple[int, int]] | None, src: str, map_path: str) -> np.ndarray:
    """``image`` (``H x W x C`` as read, turned as its EXIF orientation says) in the frame the ST map at
    ``map_path`` addresses: as shown, or as stored (a view, not a copy). ``map_size`` is the map's own (w, h),
    ``recorded`` the source spec and size its mark records (None: none). Raises :class:`~lenslab.errors.WarpError`
    naming both sizes where ``recorded`` addresses neither frame (:func:`addresses`)."""
    orientation = meta.get("exif_orientation", 1)
    shown = (image.shape[1], image.shape[0])
    stored = shown[::-1] if orientation in (5, 6, 7, 8) else shown
    if recorded is not None:
        fit = {frame: addresses(recorded, frame) for frame in {shown, stored}}
        size = recorded[1]
    else:
        fit = {frame: fits(map_size, frame) for frame in {shown, stored}}
        size = map_size
    if recorded is not None and not any(fit.values()):
        as_stored = f" ({stored[0]}x{stored[1]} as stored, EXIF orientation {orientation})" if stored != shown else ""
        raise WarpError(f"{src}: the ST map {map_path} is made for a {size[0]}x{size[1]} source (its "
                        f"lenslab:stmap mark) and this image is {shown[0]}x{shown[1]}{as_stored}: it would be "
                        f"stretched; make the map for this image (lenslab stmap --source-size "
                        f"{shown[0]}x{shown[1]})")
    if stored != shown and fit[stored] and not fit[shown]:
        from lenslab.io.exif_orientation import turn

        return turn(image, {6: 8, 8: 6}.get(orientation, orientation))  # the inverse turn: the stored frame
    if orientation != 1 and fit[stored] and fit[shown]:
        warnings.warn(f"it is shown {_turned(orientation)} (EXIF orientation {orientation}); the ST map's "
                      f"source size {size[0]}x{size[1]} fits it both as stored and as shown, so the map is applied "
                      "to it as shown", UserWarning, stacklevel=2)
    return image


def _turned(orientation: int) -> str:
    from lenslab.io.exif_orientation import TURNS

    return TURNS[orientation].replace("turned ", "turned by ")


__all__ = ["fits", "same_fractions", "addresses", "recorded_source", "frame_for_map"]
