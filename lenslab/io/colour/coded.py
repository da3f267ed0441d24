"""Integer code values -> linear Rec.709 light, by what a file says of its colour: one way for every reader of
display-encoded integer samples that may carry an ICC profile or ITU-T H.273 code points (PNG with its ``iCCP``
and ``cICP`` chunks, JPEG with its ``APP2`` profile, HEIF with its ``colr`` property, ``prof``/``rICC`` or
``nclx``).

- An ICC profile that :func:`lenslab.io.colour.icc.plan` applies (matrix/TRC, grey) gives the curves and the
  colorants (:mod:`lenslab.io.colour.icc`).
- Otherwise the code points (primaries, transfer, matrix, full range): PQ and HLG become linear light as a
  PQ or HLG video does (:func:`lenslab.io.colour.png_cicp.to_linear_light`, 1.0 = 203 cd/m²); sRGB and
  BT.709 transfers (BT.601's and BT.2020's are the same curve: :data:`~lenslab.io.colour.png_cicp.SRGB_TRANSFERS`)
  are sRGB-decoded, then converted from P3-D65 or BT.2020 primaries to Rec.709
  (:func:`lenslab.io.colour.png_cicp.wide_to_709`); any other transfer is left as its code values, with a note.
- Without either: sRGB (:func:`lenslab.io.encode.decode_codes`).

Alpha (the last of 2 or 4 channels) is coverage, code / maxval; straight colour in the file becomes
premultiplied colour in memory (:mod:`lenslab.io.alpha`) wherever the colour was decoded to linear light.
"""

from __future__ import annotations

import numpy as np

from lenslab.io.alpha import premultiply

#: H.273 primaries that are Rec.709's: BT.709 (1) and unspecified (2), read with no note
REC709_POINTS = (1, 2)
#: what the notes of a PNG name as the source of its code points
CICP_CHUNK = "the PNG's cICP chunk"


def decode(codes: np.ndarray, maxval: int, where: str, attributes: dict, *, profile: bytes | None = None,
           points: tuple[int, int, int, int] | None = None, raw: bool = False, inks: bool = False,
           source: str = CICP_CHUNK) -> tuple[np.ndarray, bool, str | None]:
    """``(image, linear, gamut)`` from integer ``codes`` (H x W x C, C in 1..4, alpha last for 2 and 4).

    ``profile``: an ICC profile's bytes (already :func:`lenslab.io.colour.icc.check`-ed) to apply; its plan's
    note goes to ``attributes["icc"]``. ``points``: H.273 code points, used where no applied profile speaks;
    the notes name them as ``source`` says. ``raw``: code / maxval, nothing decoded. ``inks``: the codes are a
    CMYK JPEG's inks that the decoder gave as RGB. ``linear``: the image is linear light decoded from PQ or HLG
    (not display-encoded); ``gamut``: what gave the wide primaries the codes were converted from
    (:data:`lenslab.io.colour.gamut.WIDE_GAMUT`), or None.
    """
    from lenslab.io.encode import decode_codes

    c = codes.shape[2]
    how = None
    if profile is not None:
        from lenslab.io.colour.icc import plan

        how = plan(profile, 4 if inks else c - 1 if c in (2, 4) else c, where)
        attributes["icc"] = how.note
        if how.kind != "ignored":
            points = None  # the profile speaks for the colour
    coded = wide = None
    if points is not None:
        from lenslab.io.colour.png_cicp import SRGB_TRANSFERS

        if points[1] not in SRGB_TRANSFERS:  # PQ, HLG, linear...: the codes are not sRGB
            coded = points
        else:  # sRGB codes, on primaries that may not be Rec.709's (Display P3)
            wide = points[0]
    gamut = None
    if how is not None and how.curves:  # a matrix/TRC or grey profile: its curves, its colorants
        from lenslab.io.colour.gamut import profile_gamut
        from lenslab.io.colour.icc import decode as icc_decode

        image = icc_decode(codes, maxval, how, where)
        gamut = profile_gamut(how)
    elif coded is not None and not raw:  # code values in float64: PQ's slope would magnify a float32 rounding
        image = codes  # (to_linear_light takes them over maxval, a band at a time)
    else:
        image = decode_codes(codes, maxval, raw or coded is not None)
    linear = False
    if coded is not None and not raw:  # PQ, HLG: linear light as their video is; other transfers: codes
        from lenslab.io.colour.png_cicp import H273_NAMES, to_linear_light

        image, attributes["note"] = to_linear_light(image, coded, source, maxval=maxval)
        linear = coded[1] in (16, 18)
        gamut = f"{_short(source)} primaries {H273_NAMES[coded[0]]}" if (
            linear and c in (3, 4) and coded[0] in H273_NAMES) else None
    elif not raw and wide not in (None, *REC709_POINTS) and c in (3, 4):  # sRGB codes on P3-D65 or BT.2020
        from lenslab.io.colour.png_cicp import H273_NAMES, wide_to_709

        attributes["note"] = wide_to_709(image, wide, source)
        gamut = f"{_short(source)} primaries {H273_NAMES[wide]}" if wide in H273_NAMES else None
    if not raw and (coded is None or linear):  # straight colour in the file, premultiplied in memory
        premultiply(image)
    return image, linear, gamut


def _short(source: str) -> str:
    """``cICP`` or ``nclx``: the word a gamut note uses for the code points' source."""
    return "cICP" if source == CICP_CHUNK else "nclx"
