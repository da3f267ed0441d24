"""The OpenColorIO display transform as an output stage (``--display``/``--view``/``--colorspace``/``--ocio``):
the display's code values and the write options they need (see :mod:`lenslab.io.ocio`)."""

from __future__ import annotations


def check_display_holds(display: str, fmt, bits: int | None = None) -> None:
    """:class:`~lenslab.errors.FormatError` when format record ``fmt`` cannot hold what ``display`` gives:
    an HDR display's (PQ, HLG) codes need 16-bit samples (not JPEG, not ``--bits 8``) and a file that says
    they are PQ or HLG (PNG's cICP chunk, a video's transfer tag: TIFF, PPM and EXR have no such tag); an
    extended-range display (beyond SDR, neither PQ nor HLG: code values above 1.0) is refused for every
    format; a display's codes are RGB (not PGM) and need a format that holds them (not EXR, Radiance HDR or
    PFM, which hold scene-linear light: :func:`displays_codes`). Depends on no image: commands call it before
    any work."""
    from lenslab.errors import FormatError
    from lenslab.io.ocio import is_hdr_display
    from lenslab.io.colour.png_cicp import display_code_points

    hdr = is_hdr_display(display)
    points = display_code_points(display) if hdr else None
    if hdr and points is None:  # beyond SDR but neither PQ nor HLG: code values above 1.0 (Apple's EDR)
        raise FormatError(f"{display}: an extended-range display (code values above 1.0), which no file or "
                          f"video tag here can say and {fmt.title} would clip: use 'Display P3 - Display' (SDR), "
                          "'ST2084-P3-D65 - Display' (PQ, to PNG or video), or EXR without --display (linear light)")
    accepts = fmt.write_options
    if hdr and "sample_type" not in accepts and "bits" in accepts and not any(b >= 16 for b in fmt.bit_depths):
        raise FormatError(f"{display}: an HDR display needs 16-bit samples; {fmt.title} holds 8: write PNG")
    if hdr and bits == 8:
        raise FormatError(f"{display}: an HDR display needs 16-bit samples; drop --bits 8")
    if points is not None and "cicp" not in accepts and fmt.kind != "video":
        what = "HLG" if points[1] == 18 else "PQ"
        raise FormatError(f"{display}: {fmt.title} has no tag that says its samples are {what}-encoded (readers "
                          f"would take them for sRGB): write PNG (its cICP chunk says Rec.2100 {what}), a video "
                          "clip (its transfer tag), or EXR without --display (linear light)")
    if not displays_codes(fmt):
        from lenslab.io.registry import formats

        names = [f.name for f in formats().values() if f.writable and f.kind == "image" and displays_codes(f)
                 and 3 in f.channels]
        raise FormatError(f"{display}: a display transform gives display code values and {fmt.title} holds "
                          f"scene-linear light: write {', '.join(names[:-1])} or {names[-1]}, or leave --display out")
    if 3 not in fmt.channels:
        holds = " or ".join(str(n) for n in fmt.channels)
        raise FormatError(f"{display}: a display's code values are RGB; {fmt.title} holds {holds} channel(s): "
                          "write PPM, PNG or TIFF")


def displays_codes(fmt) -> bool:
    """Whether format record ``fmt`` can hold a display's code values: a display format, a float format written
    with integer samples (TIFF), or one that stores the values it is given as they are (``raw``); a video
    clip says its transfer in its tags. EXR, Radiance HDR and PFM hold scene-linear light."""
    return fmt.kind == "video" or not fmt.hdr or bool({"raw", "sample_type"} & set(fmt.write_options))


def check_display_outputs(display: str | None, formats, bits: int | None = None) -> None:
    """:func:`check_display_holds` for each output format record of a command, before any work: a format
    that cannot hold what ``--display`` (and ``--bits``) ask for is a usage error."""
    from lenslab.errors import FormatError, UsageError

    for fmt in formats if display else ():
        try:
            check_display_holds(display, fmt, bits)
        except FormatError as exc:
            raise UsageError(str(exc)) from None


def apply_display(image, fmt, options: dict) -> tuple:
    """(display-encoded image, write options it needs) for format record ``fmt``.

    HDR displays (PQ, HLG) need 16 bits: PNG, PPM and TIFF are written with 16-bit samples, and an
    8-bit format is refused; a PNG also gets the display's ``cICP`` chunk (Rec.2100 PQ or HLG; an SDR
display on other primaries than Rec.709's, Display P3, gets one too: P3-D65 primaries, sRGB transfer; PNG, JPEG
    and TIFF get its ICC profile, :mod:`lenslab.io.colour.icc_build`, for readers that do not read cICP). The code values are stored as they are (``raw``), not sRGB-encoded again.
    With alpha (premultiplied ``image``) the transform acts on the straight colour and the codes are kept
    as the format keeps colour (its record's ``straight_alpha``); a format without alpha gets the colour
    over black.
    """
    from lenslab.io.ocio import display_transform, is_hdr_display

    display = options["display"]
    hdr = is_hdr_display(display)
    bits = options.get("bits")
    check_display_holds(display, fmt, bits)
    extra: dict = {}
    accepts = fmt.write_options
    if "sample_type" in accepts:  # TIFF: integers of the asked depth, 16 by default
        extra["sample_type"] = f"uint{bits or 16}"
    elif "bits" in accepts and (hdr or bits == 16) and any(b >= 16 for b in fmt.bit_depths):
        extra["bits"] = 16
    if "raw" in accepts:
        extra["raw"] = True
    from lenslab.io.colour.png_cicp import display_code_points

    points = display_code_points(display)
    if points is not None and "cicp" in accepts:  # PNG: say PQ, HLG or P3 primaries, or readers take sRGB
        extra["cicp"] = points
    if points is not None and not hdr and "icc" in accepts:  # SDR on P3: an ICC profile for readers without cICP
        from lenslab.io.colour.icc_build import display_profile

        extra["icc"] = display_profile(points)
    elif points is not None and not hdr and fmt.kind != "video":  # (HDR ones are refused before any work)
        import warnings

        warnings.warn(f"{display}: {fmt.title} has no tag for these primaries; readers will take the codes for "
                      "sRGB on Rec.709 (write PNG, JPEG or TIFF, which carry an ICC profile)", UserWarning,
                      stacklevel=2)
    transform = lambda x, a: display_transform(x, display, options.get("view"), options.get("colorspace"),  # noqa: E731
                                               options.get("ocio"), alpha_channel=a)
    from lenslab.io.alpha import has_alpha, premultiply, unpremultiply

    alpha = has_alpha(image, options.get("alpha"))  # the image's names where given (only A is alpha)
    if not alpha or not fmt.alpha:  # no alpha kept: the colour over black
        colour = image[..., :-1] if alpha else image
        return transform(colour, False), extra
    # the display's code values of the straight colour; premultiplied by alpha where the file keeps
    # premultiplied colour (EXR, float TIFF), straight where it keeps straight colour (PNG, integer TIFF)
    out = transform(unpremultiply(image, True), True)
    sample = "uint" if "bits" in accepts or str(extra.get("sample_type", "")).startswith("uint") else "float"
    return (out if fmt.holds_straight(sample) else premultiply(out, True)), extra
