"""The last stage of a warp, shared by a still image and each frame of a clip written as image files: develop
for the output format, keep or drop alpha, write."""

from __future__ import annotations


def write_warped(dst_path, colour, alpha, meta: dict, fmt, job, camera, source_alpha: bool = False,
                 given_up: bool = False) -> None:
    """Develop a warped image (premultiplied ``colour`` and its ``alpha``: the source's own, warped like colour,
    or the coverage) for format record ``fmt`` as ``job`` says and write it; an output that keeps no alpha gets
    the colour over black. ``camera``: the output's, stored where the format holds one. ``source_alpha``:
    whether the source carried alpha (with ``--compat v360`` a display output has alpha only then, as
    ffmpeg's has: ``tests/warp/test_v360_channels.py``). ``given_up``: the caller keeps neither array (a still
    image's warp), so the output is developed and encoded in their memory (colour and alpha drawn into the
    channels of one image by :func:`output_arrays` are that image): no other float image of the output's size."""
    from lenslab.io import write
    from lenslab.io.alpha import joined_alpha, with_alpha
    from lenslab.jobs.stages import Look, develop, encode_options

    from lenslab.jobs.pixel_types import pixel_type_options

    keep = keeps_output_alpha(fmt, job, meta, source_alpha)
    samples = pixel_type_options(job.pixel_type, "half")  # --pixel-type, checked against fmt by the command
    bits = samples.pop("bits", None) or (v360_bits(fmt, meta) if job.compat == "v360" else None)
    if keep:
        joined = joined_alpha(colour, alpha) if given_up and colour.shape[2] + 1 in fmt.channels else None
        colour = with_alpha(colour, alpha, fmt.channels) if joined is None else joined
    alpha = None  # (joined, or not written: its memory goes here when the caller gave it up)
    look = Look(tone=job.tone, tone_given=job.tone_given, exposure=job.exposure, display=job.display, view=job.view,
                colorspace=job.colorspace, ocio=job.ocio, bits=bits)
    # with alpha, the image developed is a new array of this function's own: the look may work in its memory
    from lenslab.current_input import from_input

    # a note on colours outside sRGB counts the warped image's pixels, not the input's; negatives past a
    # codec's undershoot are the resampling filter's lobes
    with from_input(resampled=True):
        result, shown = develop(colour, meta, fmt, look, in_place=keep or given_up, of=f"the warped image {dst_path}")
    del colour
    opts = encode_options(fmt, {**meta, "camera": None}, {**samples, "bits": bits},
                          camera=camera, channels=result.shape[2])
    if (keep or given_up) and "in_place" in fmt.write_options:  # the codes or halves made in its memory
        opts["in_place"] = True
    write(dst_path, result, format=fmt.name, overwrite=job.overwrite, **{**opts, **shown})


def keeps_output_alpha(fmt, job, meta: dict, source_alpha: bool) -> bool:
    """Whether the warped image is written with alpha to format record ``fmt`` (see :func:`write_warped`)."""
    from lenslab.jobs.stages import keeps_alpha

    keep = keeps_alpha(fmt, not job.no_alpha)
    if keep and job.compat == "v360" and (not fmt.hdr or v360_bits(fmt, meta)):  # v360 keeps its input's pixel
        keep = source_alpha  # format (ffmpeg 5.1): an RGB source, an RGB PNG or TIFF, black where v360 writes zeros
    return keep


def output_arrays(shape: tuple[int, int], channels: int, fmt, job, meta: dict, source_alpha: bool):
    """``into`` arrays for the warp of an image of ``channels`` channels into ``shape`` (h, w): the channels of the
    one image :func:`write_warped` writes (:func:`lenslab.io.alpha.room_for_alpha`); or ``(None, None)``, the
    engine's own image and no coverage kept (a source whose alpha the warp carries as its last channel, which is
    the output's alpha, or an output without alpha); or None (the engine's own: a format that takes no channel
    more)."""
    from lenslab.io.alpha import room_for_alpha

    if source_alpha or not keeps_output_alpha(fmt, job, meta, source_alpha):
        return None, None
    if channels + 1 not in fmt.channels:
        return None
    return room_for_alpha(shape[0], shape[1], channels)


def v360_bits(fmt, meta: dict) -> int | None:
    """With ``--compat v360``, the depth of the source's display codes (8 or 16: a PNG, a JPEG) where the output
    format holds integer samples of that depth (PNG, TIFF): v360 keeps its input's pixel format, so ffmpeg writes
    an 8-bit TIFF from an 8-bit PNG and a 16-bit PNG or TIFF from a 16-bit PNG (``tests/warp/test_v360_tiff.py``).
    None otherwise: a float source stays float (lenslab keeps HDR values, where ffmpeg clamps them to 16 bits)."""
    bits = meta.get("bit_depth")
    if meta.get("sample_type") == "uint" and meta.get("display_encoded") and bits in (8, 16) and \
            bits in fmt.bit_depths and "uint" in fmt.sample_types and {"bits", "sample_type"} & set(fmt.write_options):
        return int(bits)
    return None


def note_softening(job, plan) -> None:
    """A note when ``--antialias`` met a view that shrinks its source nowhere (:mod:`lenslab.warp.minification`),
    where it only softens the image: a note on the command, which a batch prints once whatever the number of its
    files, threads and cluster workers (:class:`~lenslab.jobs.funnel.CommandNote`)."""
    import warnings

    from lenslab.jobs.funnel import CommandNote
    from lenslab.warp.minification import NOTE, shrinks

    if shrinks(plan) is False:
        warnings.warn(CommandNote(NOTE), stacklevel=2)


__all__ = ["write_warped", "keeps_output_alpha", "output_arrays", "v360_bits", "note_softening"]
