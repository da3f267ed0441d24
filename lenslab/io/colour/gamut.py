"""Colours outside the output's gamut: a file on primaries wider than Rec.709's (Display P3, Adobe RGB, BT.2020
in an ICC profile or a PNG cICP chunk) holds colours that Rec.709 (sRGB's primaries, lenslab's working space)
cannot show. Converted to linear Rec.709 (:mod:`lenslab.io.colour.primaries`), such a colour has a negative
component: its chromaticity lies outside the sRGB triangle. That is no damage of the file, and no codec's
undershoot: a display output (an sRGB PNG or JPEG, a tone-mapped image) clips it per channel, and the command
says how many pixels were clipped, in those words (:func:`clip_outside`).

A reader that converts integer codes (which hold no negative value of their own) from such primaries names them
in the image's ``meta[WIDE_GAMUT]``; every negative component of that image is then a colour outside the gamut.
Float files (EXR, float TIFF) may hold negatives of their own and are not named: their negatives stay the tone
curve's repairs.
"""

from __future__ import annotations

import warnings

import numpy as np

#: ``meta`` key a reader sets to what gave the wide primaries it converted integer codes from (``ICC profile
#: 'Display P3'``, ``cICP primaries P3-D65``)
WIDE_GAMUT = "wide_gamut"
#: rows looked at a time: no temporary of the image's size
BAND_ROWS = 256


class GamutWarning(UserWarning):
    """Pixels whose colour lies outside the output's gamut were clipped per channel; ``pixels`` of ``total``."""

    def __init__(self, message: str, pixels: int = 0, total: int = 0):
        super().__init__(message)
        self.pixels, self.total = int(pixels), int(total)


def outside(image: np.ndarray, alpha: bool) -> int:
    """How many pixels of ``image`` (float32 H x W x C, alpha last when ``alpha``) have a negative colour
    component."""
    colour = image[..., :-1] if alpha else image
    return sum(int((colour[r:r + BAND_ROWS].min(axis=-1) < 0).sum()) for r in range(0, image.shape[0], BAND_ROWS))


def clip_outside(image: np.ndarray, meta: dict, alpha: bool, in_place: bool = False) -> np.ndarray:
    """``image`` (float32 H x W x C, premultiplied colour, alpha last when ``alpha``) with the negative colour
    components of a wide-gamut file (``meta[WIDE_GAMUT]``) set to 0, per channel, as a display output clips
    them, and a :class:`GamutWarning` that counts the pixels: ``FILE: N of M pixels hold colours outside the
    sRGB gamut (the file's ICC profile 'Display P3'): clipped per channel``. ``in_place``: the caller gives
    ``image`` up; else it is copied when something is clipped. Any other image is returned as it is."""
    name = meta.get(WIDE_GAMUT)
    if not name or getattr(image, "ndim", 0) != 3 or image.shape[2] - bool(alpha) != 3:
        return image
    count = outside(image, alpha)
    if not count:
        return image
    if not in_place or not image.flags.writeable:
        image = image.copy()
    colour = image[..., :-1] if alpha else image
    for r in range(0, image.shape[0], BAND_ROWS):
        np.maximum(colour[r:r + BAND_ROWS], 0.0, out=colour[r:r + BAND_ROWS])
    total = image.shape[0] * image.shape[1]
    text = (f"{count} of {total} pixel{'s' if total != 1 else ''} hold colours outside the sRGB gamut (the "
            f"file's {name}): clipped per channel")
    warning = GamutWarning(f"{meta.get('path', 'the image')}: {text}", count, total)
    warning.command_line = text  # a batch's note names the file itself
    warnings.warn(warning, stacklevel=2)
    return image


__all__ = ["WIDE_GAMUT", "GamutWarning", "clip_outside", "outside"]
