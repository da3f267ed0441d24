"""One file warped as ``lenslab warp`` does it, here or on a cluster worker: an image (read, warp through
the plan cache, tone-map or display-transform, write) or a clip (:mod:`lenslab.cli.warp_video`)."""

from __future__ import annotations

from pathlib import Path


def warp_one(src_path: str, dst_path: Path, args, cache, progress=None) -> None:
    """Warp ``src_path`` to ``dst_path`` with the command's options ``args`` and the maps of ``cache``."""
    import numpy as np

    from lenslab.cli.policy import check_output
    from lenslab.cli.warp_cameras import autoscale_camera, default_size, output_camera, source_camera
    from lenslab.cli.warp_video import is_video, warp_video
    from lenslab.errors import FormatError
    from lenslab.io import read, write
    from lenslab.io.detect import format_for_path
    from lenslab.io.alpha import split_alpha, with_alpha
    from lenslab.io.registry import get, hdr_formats

    if is_video(src_path):  # every frame with one map, to a video
        return warp_video(src_path, dst_path, args, cache)
    fmt = format_for_path(dst_path, None)
    check_output(dst_path, [src_path], args.overwrite)
    image, meta = read(src_path)
    if args.stmap:
        from lenslab.stmap import warp_with_st_map

        dst = None
        colour, alpha = split_alpha(*warp_with_st_map(image, args.st, args.filter, args.samples, args.antialias,
                                                      progress=progress))
    else:
        src = source_camera(args.source, meta, image.shape)
        size = args.size or default_size(args.to, image.shape[0])
        dst = output_camera(args, src, size)
        if args.autoscale:
            dst = autoscale_camera(src, dst, args.autoscale, args.samples, args.quiet, args.verbose)
        colour, alpha = cache.warp_frame(image, src, dst, progress=progress)  # as every video frame is
    out_format = get(fmt)
    keep_alpha = not args.no_alpha and out_format.alpha  # the format's record says whether it holds alpha
    exposure = args.exposure
    shown: dict = {}
    if getattr(args, "display", None):  # an OpenColorIO display transform instead of the tone curve
        from lenslab.cli.display import apply_display

        if exposure == "auto":
            raise FormatError("--exposure auto goes with --tone; give a number of stops with --display")
        lit = colour * np.float32(2.0 ** float(exposure))
        rgba = np.concatenate([lit, alpha[..., None]], axis=-1) if keep_alpha else lit  # else: over black
        mapped, shown = apply_display(rgba, out_format, {**vars(args), "bits": None})
        colour = mapped[..., :-1] if keep_alpha else mapped
    elif fmt not in hdr_formats() and (not meta["display_encoded"] or exposure == "auto"):
        from lenslab.tone import tonemap

        rgba = np.concatenate([colour, alpha[..., None]], axis=-1)
        mapped = tonemap(rgba, curve=args.tone, exposure=exposure)
        colour, alpha = mapped[..., :-1], mapped[..., -1]
    elif exposure == "auto":
        raise FormatError("--exposure auto applies when writing display formats (png, jpg, ppm, pgm)")
    elif float(exposure) != 0.0:
        colour = colour * np.float32(2.0 ** float(exposure))
    opts: dict = {}
    if keep_alpha:
        result = with_alpha(colour, alpha, out_format.channels)
        if result.shape[2] == 2 and "channels" in out_format.write_options:
            opts["channels"] = ["Y", "A"]
    else:
        result = colour
    if fmt == "exr":
        opts["camera"] = dst
        opts["pixel_type"] = args.pixel_type
    opts.update(shown)
    write(dst_path, result, format=fmt, overwrite=args.overwrite, **opts)


def plan_cache(args):
    """The plans (maps) of this command's warps, one per geometry, made once and reused."""
    from lenslab.warp import WarpPlan
    from lenslab.warp.batch import PlanCache

    factory = WarpPlan
    if args.compat == "v360":
        from lenslab.warp.compat_v360 import V360Plan as factory
    return PlanCache(factory=factory, filter=args.filter, samples=args.samples, antialias=args.antialias,
                     seed=args.seed, allow_parallax=args.allow_parallax, exact_map=args.exact_map)
