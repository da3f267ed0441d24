"""Colours outside the output's gamut: a file on primaries wider than Rec.709's (Display P3, Adobe RGB, BT.2020
in an ICC profile or a PNG cICP chunk) holds colours that Rec.709 (sRGB's primaries, lenslab's working space)
cannot show. Converted to linear Rec.709 (:mod:`lenslab.io.colour.primaries`), such a colour has a negative
component: its chromaticity lies outside the sRGB triangle. That is no damage of the file, and no codec's
undershoot: a display output (an sRGB PNG or JPEG, a tone-mapped image) clips it per channel, and the command
says how many pixels were clipped, in those words (:func:`clip_outside`).

A reader that converts a file's colours from such primaries (:func:`widens`: not sRGB's own) names them in
the image's ``meta[WIDE_GAMUT]`` when the file held no negative value of its own (integer codes never do; a
float file, EXR or TIFF, is looked at before the conversion): every negative component of that image is then
a colour outside the gamut. A float
file with negatives of its own is not named: its negatives stay the tone curve's repairs, small undershoot
and real negative light alike (:mod:`lenslab.tone.repairs`).
"""

from __future__ import annotations

import contextlib
import contextvars
import warnings
from typing import Iterator

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


class GamutTally:
    """The colours outside the sRGB gamut that :func:`clip_outside` clipped in the frames of one clip, for one
    note on the clip: ``CLIP: N of M pixels in F of T frames hold colours outside the sRGB gamut (the frames'
    ICC profile 'Display P3'): clipped per channel``, where M counts every frame's pixels."""

    def __init__(self):
        self.pixels, self.frames, self.names = 0, 0, {}

    def add(self, count: int, name: str) -> None:
        self.pixels += int(count)
        self.frames += 1
        self.names[name] = None

    def warn(self, output: str, frames: int, frame_pixels: int) -> None:
        """The clip's one :class:`GamutWarning` (none when nothing was clipped): ``frames`` frames of
        ``frame_pixels`` pixels each were written to ``output``."""
        if not self.pixels:
            return
        total = int(frames) * int(frame_pixels)
        text = (f"{self.pixels} of {total} pixels in {self.frames} of {frames} frame{'s' if frames != 1 else ''} "
                f"hold colours outside the sRGB gamut (the frames' {', '.join(self.names)}): clipped per channel")
        warning = GamutWarning(f"{output}: {text}", self.pixels, total)
        warning.command_line = text
        warnings.warn(warning, stacklevel=2)


_TALLY: contextvars.ContextVar[GamutTally | None] = contextvars.ContextVar("gamut_tally", default=None)


@contextlib.contextmanager
def tallied() -> Iterator[GamutTally]:
    """Within the block, :func:`clip_outside` (in this thread) counts into the tally it yields instead of
    warning once per image: the frames of a clip, whose note is the tally's :meth:`GamutTally.warn`."""
    tally = GamutTally()
    token = _TALLY.set(tally)
    try:
        yield tally
    finally:
        _TALLY.reset(token)


def widens(matrix: np.ndarray) -> bool:
    """Whether the 3 x 3 matrix (file RGB -> linear Rec.709) takes some colour of the file's own gamut outside
    Rec.709's: one of its entries is negative beyond the precision of the file's primaries. A profile on sRGB's
    own primaries with another curve (scRGB, esRGB, a gamma 2.2 "sRGB") gives entries of about -1e-4 (its
    s15.16 colorants and their Bradford adaptation; colour-science's own sRGB -> BT.709 matrix has -8e-5): no
    colour of such a file is outside, and the few 1e-4 below 0 it takes stay the tone curve's slight repairs.
    The bound is the one within which a profile's matrix is sRGB's (``icc.SRGB_MATRIX_TOLERANCE``); Display P3
    gives -0.22, Adobe RGB -0.40."""
    from lenslab.io.colour.icc import SRGB_MATRIX_TOLERANCE

    return bool(np.min(np.asarray(matrix, dtype=np.float64)) < -SRGB_MATRIX_TOLERANCE)


def profile_gamut(how) -> str | None:
    """What :data:`WIDE_GAMUT` says for codes converted by the ICC plan ``how``
    (:func:`lenslab.io.colour.icc.plan`): ``ICC profile 'NAME'`` when its matrix :func:`widens`, else None."""
    return f"ICC profile '{how.name}'" if how.matrix is not None and widens(how.matrix) else None


#: How far below 0 a component of a converted colour may lie and still be the gamut's edge, relative to the
#: pixel's largest component magnitude m. The conversion is y = M x (file RGB x -> linear Rec.709 y); taken
#: back, x = N y with N (Rec.709 -> the wider primaries) non-negative, rows summing to 1, so every |x_j| <= m.
#: Two errors move y_i: (1) M's entries are known to the primaries' precision d: an ICC profile's colorants
#: are s15.16 numbers (2^-16 a step), adapted to D65 and inverted, and Ghostscript's Adobe RGB gives an entry
#: of -1.6e-5 where the exact one is 0 (its red is sRGB's red: red 51 reads G = -5.8e-8 beside R = 0.041);
#: colour-science's Adobe RGB matrix, from the standard's four-decimal numbers, has -1.03e-5 there. With
#: d = 2^-15 the error is at most d * sum_j |x_j| <= 3 d m. (2) float32: the curve's table values and the
#: result are rounded (eps/2 each, eps = 2^-23) and the sums run in float64, at most 2 eps * sum_j |M_ij x_j|
#: <= 2 eps * ROW * m, ROW = 2.33 the largest absolute row sum of the matrices met (BT.2020 -> Rec.709;
#: Display P3 1.45, Adobe RGB 1.80); 4 eps * ROW leaves a factor two. Float32 alone would be 1.1e-6 of m: the
#: profile's precision is what sets the bound, 9.3e-5 of m, a third of an 8-bit code at white after sRGB's
#: 12.92 slope (a clip that small changes no code a display shows).
EDGE = 3 * 2.0 ** -15 + 4 * 2.0 ** -23 * 2.33


def outside(image: np.ndarray) -> int:
    """How many pixels of ``image`` (float H x W x C, the colour in its first three channels) have a colour
    component below ``-EDGE`` times the pixel's largest component magnitude (:data:`EDGE`: the rounding of
    the conversion, not a colour outside; NaN is not negative), a band of whole rows at a time, every channel
    read in its memory order: a band whose minimum is not negative is passed at once (the minimum runs at
    memory speed; a negative of another channel, alpha or depth, only sends its band to the next step). In a
    band with a negative, the signs, one byte a component, are or-ed over the three colour columns, and only
    the pixels with a negative (found in the rows that have one) are weighed against the edge. Measured on an
    8K image with a negative on every seventh row (load 4.7): 0.08 s of CPU for RGB, 0.09 s for RGBA (0.06 s
    and 0.07 s counting every negative, without the edge), where the per-pixel minimum of three strided
    channels took 0.17 s."""
    return _weigh(image)[0]


def negative_pixels(image: np.ndarray) -> int:
    """How many pixels of ``image`` (as :func:`outside`) have any colour component below 0, however little:
    whether a float file holds negatives of its own, before a reader converts its primaries."""
    return _weigh(image)[1]


def _weigh(image: np.ndarray) -> tuple[int, int]:
    """(:func:`outside`'s count, :func:`negative_pixels`'s count)."""
    count, channels, negatives = 0, image.shape[2], 0
    for r in range(0, image.shape[0], BAND_ROWS):
        band = image[r:r + BAND_ROWS]
        if band.min() >= 0:  # (NaN compares False: such a band is looked at pixel by pixel)
            continue
        signs = (band < 0).view(np.uint8).reshape(-1, channels)  # a new contiguous array: a byte a component
        negative = (signs[:, 0] | signs[:, 1] | signs[:, 2]).reshape(band.shape[:2])
        negatives += int(np.count_nonzero(negative))
        rows = np.flatnonzero(negative.max(axis=1))  # the rows with a negative, then their pixels with one
        where = np.nonzero(negative[rows])
        colours = band[rows[where[0]], where[1], :3].astype(np.float64)
        low = np.fmin.reduce(colours, axis=1)  # (a NaN beside a negative: the negative counts)
        count += int(np.count_nonzero(low < -EDGE * np.fmax(np.fmax.reduce(colours, axis=1), -low)))
    return count, negatives


def clip_outside(image: np.ndarray, meta: dict, alpha: bool, in_place: bool = False,
                 of: str | None = None) -> np.ndarray:
    """``image`` (float32 H x W x C, premultiplied colour, alpha last when ``alpha``) with the negative colour
    components of a wide-gamut file (``meta[WIDE_GAMUT]``) set to 0, per channel, as a display output clips
    them, and a :class:`GamutWarning` that counts the pixels: ``FILE: N of M pixels hold colours outside the
    sRGB gamut (the file's ICC profile 'Display P3'): clipped per channel``. ``of``: what ``image`` is when it
    is not the file's own pixels (``the warped image out.png``): the note then counts the pixels of that
    (``N of M pixels of the warped image out.png hold ...``). Within :func:`tallied` the count goes to the
    tally instead (a clip's frames: one note for the clip). ``in_place``: the caller gives ``image`` up; else it
    is copied when something is clipped. Any other image is returned as it is."""
    name = meta.get(WIDE_GAMUT)
    if not name or getattr(image, "ndim", 0) != 3 or image.shape[2] - bool(alpha) != 3:
        return image
    count, negatives = _weigh(image)
    if not negatives:
        return image
    if not in_place or not image.flags.writeable:
        image = image.copy()
    for r in range(0, image.shape[0], BAND_ROWS):  # whole pixels, in memory order; alpha put back as it was
        band = image[r:r + BAND_ROWS]
        kept = band[..., -1].copy() if alpha else None
        np.maximum(band, 0.0, out=band)
        if alpha:
            band[..., -1] = kept
    total = image.shape[0] * image.shape[1]
    if not count:  # the gamut's edge alone, within the conversion's rounding: clipped, nothing to say
        return image
    tally = _TALLY.get()
    if tally is not None:
        tally.add(count, name)
        return image
    text = (f"{count} of {total} pixel{'s' if total != 1 else ''}{f' of {of}' if of else ''} hold colours outside "
            f"the sRGB gamut (the file's {name}): clipped per channel")
    warning = GamutWarning(f"{meta.get('path', 'the image')}: {text}", count, total)
    warning.command_line = text  # a batch's note names the file itself
    warnings.warn(warning, stacklevel=2)
    return image


__all__ = ["EDGE", "WIDE_GAMUT", "GamutTally", "GamutWarning", "clip_outside", "negative_pixels", "outside",
           "profile_gamut", "tallied", "widens"]
