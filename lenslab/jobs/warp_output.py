"""The last stage of a warp, shared by a still image and each frame of a clip written as image files: develop
for the output format, keep or drop alpha, write."""

from __future__ import annotations


def write_warped(dst_path, colour, alpha, meta: dict, fmt, job, camera, source_alpha: bool = False) -> None:
    """Develop a warped image (premultiplied ``colour`` and its ``alpha``: the source's own, warped like colour,
    or the coverage) for format record ``fmt`` as ``job`` says and write it; an output that keeps no alpha gets
    the colour over black. ``camera``: the output's, stored where the format holds one. ``source_alpha``:
    whether the source carried alpha (with ``--compat v360`` a display output has alpha only then, as
    ffmpeg's has: ``tests/warp/test_v360_channels.py``)."""
    from lenslab.io import write
    from lenslab.io.alpha import with_alpha
    from lenslab.jobs.stages import Look, develop, encode_options, keeps_alpha

    keep = keeps_alpha(fmt, not job.no_alpha)
    if keep and job.compat == "v360" and not fmt.hdr:  # v360 keeps its input's pixel format (ffmpeg 5.1): an
        keep = source_alpha  # RGB source, an RGB PNG, black where v360 writes zeros (the colour over black)
    look = Look(tone=job.tone, exposure=job.exposure, display=job.display, view=job.view,
                colorspace=job.colorspace, ocio=job.ocio)
    # with alpha, the image developed is a new array of this function's own: the look may work in its memory
    from lenslab.current_input import from_input

    # a note on colours outside sRGB counts the warped image's pixels, not the input's; negatives past a
    # codec's undershoot are the resampling filter's lobes
    with from_input(resampled=True):
        result, shown = develop(with_alpha(colour, alpha, fmt.channels) if keep else colour, meta, fmt, look,
                                in_place=keep, of=f"the warped image {dst_path}")
    opts = encode_options(fmt, {**meta, "camera": None}, {"pixel_type": job.pixel_type}, camera=camera,
                          channels=result.shape[2])
    write(dst_path, result, format=fmt.name, overwrite=job.overwrite, **{**opts, **shown})


def note_softening(job, plan) -> None:
    """A note when ``--antialias`` met a view that shrinks its source nowhere (:mod:`lenslab.warp.minification`),
    where it only softens the image: a note on the command, which a batch prints once whatever the number of its
    files, threads and cluster workers (:class:`~lenslab.jobs.funnel.CommandNote`)."""
    import warnings

    from lenslab.jobs.funnel import CommandNote
    from lenslab.warp.minification import NOTE, shrinks

    if shrinks(plan) is False:
        warnings.warn(CommandNote(NOTE), stacklevel=2)


__all__ = ["write_warped", "note_softening"]
