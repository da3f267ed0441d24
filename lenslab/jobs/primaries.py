"""``--primaries`` of ``lenslab tonemap`` and ``lenslab compare-tones``: the primaries whose luminance weights (the Y row of their RGB -> XYZ
matrix) the exposure and the curve use, for an image whose values are on those primaries.

Every reader converts a file's colour to linear Rec.709 (sRGB's primaries) when the file says what its
primaries are: an ICC profile, a PNG cICP chunk, an EXR ``chromaticities`` attribute. Such an image's values
are on Rec.709 whatever the file held, so sRGB's weights are the right ones and another ``--primaries`` would
weigh the channels wrongly: it is not applied, and a note says why. ``--primaries`` is for files without
such a tag whose values are on other primaries (a PFM, an untagged EXR written in ACEScg or Display P3).
"""

from __future__ import annotations

import warnings

#: what the weights are when no --primaries is given, and for a file read onto Rec.709
WORKING = "sRGB"


def check_primaries(primaries: str | None, mode: str, exposure, curves, display: str | None = None) -> None:
    """A usage error (before any file is read) when ``--primaries`` has nothing to weigh: with ``--display``
    instead of a curve (the OpenColorIO view maps colour itself), or when neither ``--luminance``,
    ``--exposure auto`` nor one of ``curves`` that reads the image's luminance (``kind`` ``image`` or
    ``local``) is in use; an unknown colourspace name is refused here too."""
    from lenslab.errors import ToneError, UsageError

    if primaries is None:
        return
    if display:
        raise UsageError("--primaries sets the luminance weights of a tone curve; --display maps colour through "
                         "OpenColorIO and uses none: leave --primaries out")
    auto = str(exposure).strip().lower() == "auto"
    if mode != "luminance" and not auto and all(c.kind not in ("image", "local") for c in curves):
        named = ", ".join(c.name for c in curves)
        raise UsageError(f"--primaries has no effect here: its luminance weights apply with --luminance, "
                         f"--exposure auto or a curve that reads luminance (not {named} per channel)")
    from lenslab.tone import luminance_weights

    try:
        luminance_weights(primaries)
    except ToneError as e:
        raise UsageError(f"--primaries: {e}") from None


def converted_from(meta: dict) -> str | None:
    """What in the file told the reader its primaries and had its colour converted to Rec.709 (``the EXR's
    chromaticities attribute``, ``its ICC profile``, ``its cICP chunk``), or None for an untagged file."""
    from lenslab.io.colour.gamut import WIDE_GAMUT

    if meta.get("primaries_converted_to_rec709"):
        return "its chromaticities attribute"
    if meta.get(WIDE_GAMUT):
        return f"its {meta[WIDE_GAMUT]}"
    attrs = meta.get("attributes") or {}
    icc = attrs.get("icc")
    if isinstance(icc, str) and "not applied" not in icc:
        return "its ICC profile"
    if attrs.get("cICP"):
        return "its cICP chunk"
    return None


def applied_primaries(primaries: str | None, meta: dict) -> str:
    """The primaries whose weights apply to an image read with ``meta``: ``primaries`` (None: sRGB) for an
    untagged file; sRGB for a file whose colour the reader converted to Rec.709, with a
    :class:`lenslab.tone.ToneWarning` when another name was asked."""
    source = converted_from(meta)
    if primaries is None or source is None:
        return primaries or WORKING
    from lenslab.tone import luminance_weights

    if luminance_weights(primaries).tolist() != luminance_weights(WORKING).tolist():
        from lenslab.tone import ToneWarning

        warnings.warn(ToneWarning(f"--primaries {primaries} not applied: the file's colour was converted to "
                                  f"Rec.709 primaries from {source} when read, so sRGB's luminance weights apply"))
    return WORKING


__all__ = ["WORKING", "applied_primaries", "check_primaries", "converted_from"]
