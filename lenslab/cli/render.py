"""What a display or HDR output stores: the tone curve or OpenColorIO display transform, exposure, and
the output format's write options, for ``convert`` (images and video frames)."""

from __future__ import annotations


def render(image, meta: dict, options: dict):
    """(image as the output format stores it, write options): tone curve or display transform for
    display outputs, exposure, and the format's options."""
    from lenslab.errors import FormatError
    from lenslab.io.registry import get

    to, exposure = options["to"], options["exposure"]
    fmt = get(to)
    bits = options.get("bits")
    integers = bool(bits) and "sample_type" in fmt.write_options  # TIFF with --bits: display-encoded
    shown: dict = {}
    if options.get("display"):  # an OpenColorIO display transform instead of the tone curve
        from lenslab.cli.display import apply_display

        if exposure == "auto":
            raise FormatError("--exposure auto goes with --tone; give a number of stops with --display")
        from lenslab.io.alpha import expose

        image, shown = apply_display(expose(image, exposure), fmt, options)
    elif (not fmt.hdr or integers) and (not meta["display_encoded"] or exposure == "auto"):
        from lenslab.tone import tonemap

        image = tonemap(image, curve=options["tone"], exposure=exposure)
    elif exposure == "auto":
        raise FormatError("--exposure auto applies when writing display formats (jpg, png, ppm, pgm)")
    elif exposure != 0.0:
        from lenslab.io.alpha import expose

        image = expose(image, exposure)  # light, not coverage
    return image, {**write_options(fmt, meta, options), **shown}


def write_options(fmt, meta: dict, options: dict) -> dict:
    """The write options of format ``fmt`` from the command's options and what the input held.

    EXR to EXR keeps the input's float type (half or float; integer channels become float) unless
    --pixel-type says otherwise."""
    opts: dict = {}
    accepts = fmt.write_options
    pixel_type = options.get("pixel_type")
    if "quality" in accepts and options.get("quality") is not None:
        opts["quality"] = options["quality"]
    if "bits" in accepts and options.get("bits"):
        opts["bits"] = options["bits"]
    if "sample_type" in accepts:
        opts["sample_type"] = f"uint{options['bits']}" if options.get("bits") else (pixel_type or "float")
    if "pixel_type" in accepts:
        if pixel_type is None:
            kept = meta["sample_type"] if meta["format"] == fmt.name else "half"
            pixel_type = kept if kept in ("half", "float") else "float"
        opts["pixel_type"] = pixel_type
    if "compression" in accepts and fmt.name in ("exr", "tiff"):
        opts["compression"] = options.get("compression") or {"exr": "zip", "tiff": "zlib"}[fmt.name]
    if fmt.camera and meta.get("camera") is not None:
        opts["camera"] = meta["camera"]
    return opts
