"""``--display``/``--view``/``--colorspace``/``--ocio``: an OpenColorIO display transform instead of a tone
curve, shared by the commands that write display images (see :mod:`lenslab.io.ocio`)."""

from __future__ import annotations

import argparse


def add_display_arguments(parser: argparse.ArgumentParser, title: str | None = None, instead_of: str = "--tone",
                          hdr: bool = True) -> None:
    """The group of display options; ``instead_of`` names the command's tone-curve option, ``hdr`` says
    whether the command writes HDR displays (16-bit PNG/TIFF)."""
    g = parser.add_argument_group(title or f"OpenColorIO display transform (instead of {instead_of})")
    g.add_argument("--display", metavar="NAME",
                   help="display of the OpenColorIO config, e.g. sRGB, 'Display P3'"
                        + (", Rec.2100-PQ (HDR: written as 16-bit PNG/TIFF)" if hdr else " (SDR displays)")
                        + "; any unique part of the name works")
    g.add_argument("--view", metavar="NAME",
                   help="view of that display (default: the display's first), e.g. 'ACES 2.0 - SDR', "
                        "Un-tone-mapped")
    g.add_argument("--colorspace", metavar="NAME",
                   help="the input's colour space in the config (default: linear Rec.709, which lenslab reads "
                        "every file into; EXR chromaticities are converted on reading)")
    g.add_argument("--ocio", metavar="CONFIG",
                   help="OpenColorIO config file or ocio:// name (default ocio://default; "
                        "ocio://studio-config-latest adds Rec.2100-HLG)")


def display_options(args: argparse.Namespace) -> dict:
    """The display keys of a command's option dict; checks the names before any work starts."""
    opts = {k: getattr(args, k, None) for k in ("display", "view", "colorspace", "ocio")}
    if opts["display"] is None:
        for k in ("view", "colorspace", "ocio"):
            if opts[k] is not None:
                from lenslab.cli.policy import UsageError

                raise UsageError(f"--{k} goes with --display NAME")
        return opts
    from lenslab.cli.policy import UsageError
    from lenslab.io.ocio import OCIOError, processor

    try:  # unknown names: one usage error now, before any file is read
        processor(opts["display"], opts["view"], opts["colorspace"], opts["ocio"])
    except OCIOError as exc:
        raise UsageError(str(exc)) from None
    return opts


def apply_display(image, fmt, options: dict) -> tuple:
    """(display-encoded image, write options it needs) for format record ``fmt``.

    HDR displays (PQ, HLG) need 16 bits: PNG, PPM and TIFF are written with 16-bit samples, and an
    8-bit format is refused. The code values are stored as they are (``raw``), not sRGB-encoded again.
    With alpha (premultiplied ``image``) the transform acts on the straight colour and the codes are kept
    as the format keeps colour (its record's ``straight_alpha``); a format without alpha gets the colour
    over black.
    """
    from lenslab.errors import FormatError
    from lenslab.io.ocio import display_transform, is_hdr_display

    display = options["display"]
    hdr = is_hdr_display(display)
    bits = options.get("bits")
    extra: dict = {}
    accepts = fmt.write_options
    if "sample_type" in accepts:  # TIFF: integers of the asked depth, 16 by default
        extra["sample_type"] = f"uint{bits or 16}"
        bits = bits or 16
    elif "bits" in accepts:
        depths = [b for b in fmt.bit_depths if b >= 16]
        if hdr and not depths:
            raise FormatError(f"{display}: an HDR display needs 16-bit samples; {fmt.title} holds 8: write PNG or "
                              "TIFF")
        if hdr and bits == 8:
            raise FormatError(f"{display}: an HDR display needs 16-bit samples; drop --bits 8")
        if (hdr or bits == 16) and depths:
            extra["bits"] = 16
    if hdr and bits == 8:
        raise FormatError(f"{display}: an HDR display needs 16-bit samples; drop --bits 8")
    if "raw" in accepts:
        extra["raw"] = True
    transform = lambda x: display_transform(x, display, options.get("view"), options.get("colorspace"),  # noqa: E731
                                            options.get("ocio"))
    from lenslab.io.alpha import has_alpha, premultiply, unpremultiply

    if not has_alpha(image) or not fmt.alpha:  # no alpha kept: the colour over black
        c = image.shape[-1]
        colour = image[..., :c - 1] if has_alpha(image) and c > 1 else image
        return transform(colour), extra
    # the display's code values of the straight colour; premultiplied by alpha where the file keeps
    # premultiplied colour (EXR, float TIFF), straight where it keeps straight colour (PNG, integer TIFF)
    out = transform(unpremultiply(image))
    sample = "uint" if "bits" in accepts or str(extra.get("sample_type", "")).startswith("uint") else "float"
    return (out if fmt.holds_straight(sample) else premultiply(out)), extra
