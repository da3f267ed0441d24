"""Tone-map and write one file, as ``lenslab tonemap`` does: what the command, its batches and the
cluster's workers (:mod:`lenslab.cluster.tasks`) share."""

from __future__ import annotations


def write_tone_mapped(path, image, dither=True, bits=None, overwrite=True, camera=None) -> None:
    """Write display-linear values: LDR formats encode to sRGB and quantise; float formats keep them."""
    from lenslab import io
    from lenslab.io.detect import format_for_path

    options = {"overwrite": overwrite}
    fmt = format_for_path(path, None)
    if fmt not in io.HDR_FORMATS:
        options["dither"] = dither
        if bits:
            options["bits"] = bits
    if camera is not None and fmt == "exr":
        options["camera"] = camera
    io.write(path, image, **options)


def tonemap_one(src: str, dst: str, options: dict) -> str:
    """Read, tone-map and write one file as ``lenslab tonemap`` does; repairs are warnings (the batch's
    notes). Returns the output path; raises on failure."""
    from lenslab import io, tone
    from lenslab.cli.policy import check_output

    check_output(dst, [io.split_selector(src)[0]], options["overwrite"])
    image, meta = io.read(src)
    if options.get("display"):
        write_display(dst, image, options)
        return dst
    ev = options["exposure"]
    if ev == "auto":
        ev = tone.auto_exposure(image, primaries=options["primaries"])
    out = tone.tonemap(image, options["curve"], ev, options["mode"], primaries=options["primaries"],
                       **options["params"])
    write_tone_mapped(dst, out, dither=options["dither"], bits=options["bits"], overwrite=options["overwrite"],
                      camera=meta.get("camera"))
    return dst


def write_display(dst: str, image, options: dict) -> None:
    """Write ``image`` through the OpenColorIO display transform of ``options`` (``display``, ``view``,
    ``colorspace``, ``ocio``) instead of a tone curve, after ``exposure`` stops (a number)."""
    from lenslab import io
    from lenslab.cli.display import apply_display
    from lenslab.errors import FormatError
    from lenslab.io import registry
    from lenslab.io.alpha import expose

    ev = options["exposure"]
    if ev == "auto":
        raise FormatError("--exposure auto goes with a tone curve; give a number of stops with --display")
    fmt = registry.get(registry.format_for_path(dst, None))
    shown, extra = apply_display(expose(image, float(ev)), fmt, options)
    if fmt.hdr and "raw" not in extra:
        raise FormatError(f"{dst}: a display transform writes display images (png, tif, jpg, ppm); "
                          f"{fmt.name} holds scene-linear values")
    # the display's code values are stored as they come (rounded to the nearest code, as convert does)
    io.write(dst, shown, overwrite=options["overwrite"], **extra)
