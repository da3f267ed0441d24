"""``lenslab warp`` on video: every frame warped with one map, encoded with the input's rate, colour tags
and audio (see :mod:`lenslab.io.video` for the colour rules), or written as one image file per frame
(:mod:`lenslab.jobs.frame_files`)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path


def add_video_arguments(parser: argparse.ArgumentParser) -> None:
    from lenslab.io.video.codecs import CODECS

    g = parser.add_argument_group("video (MP4, MOV, MKV inputs)")
    g.add_argument("--frames", metavar="A:B", default=None, type=parse_frames,
                   help="only frames A to B-1, counted from 0 (e.g. 10:20, :50, 100:); audio is kept only for "
                        "the whole clip")
    g.add_argument("--codec", choices=tuple(CODECS), default=None,
                   help="video codec (default: by the output's extension: .mp4 h264, or h265 10-bit for a clip "
                        "written PQ or HLG (its input's transfer, or --display's); .mov prores; .mkv ffv1)")


def parse_frames(text: str | None) -> tuple[int, int | None]:
    """'A:B' -> (A, B) with B None for open ends; a usage error for anything else."""
    if not text:
        return 0, None
    head, sep, tail = text.partition(":")
    try:
        start = int(head) if head.strip() else 0
        stop = int(tail) if tail.strip() else None
    except ValueError:
        start, stop, sep = -1, None, ""
    if not sep or start < 0 or (stop is not None and stop <= start):
        raise argparse.ArgumentTypeError(f"{text!r}: give A:B with 0 <= A < B (e.g. 10:20, :50 or 100:)")
    return start, stop


def is_video(path) -> bool:
    from lenslab.io import split_selector
    from lenslab.io.registry import get, sniff

    file, _ = split_selector(path)
    try:
        return get(sniff(file)).kind == "video"
    except (OSError, ValueError):
        return False


def warp_video(src_path: str, dst_path: Path, args, cache) -> None:
    """Decode, warp every frame with the map of the first, encode (or write each to an image file when
    ``dst_path`` names an image: ``frames/%04d.png``, or ``frames/shot.png`` for ``shot.000000.png``, ...); a
    progress bar by frames."""
    import numpy as np

    from lenslab.jobs.policy import check_output
    from lenslab.jobs.warp.cameras import (autoscale_camera, default_output_size, output_camera, place_source,
                                            source_camera)
    from lenslab.errors import FormatError
    from lenslab.atomic import atomic_write_path
    from lenslab.io.video import VIDEO_EXTENSIONS, VideoWriter, probe_video, read_frames
    from lenslab.io.video.codecs import open_encoder

    image = None if Path(dst_path).suffix.lower() in VIDEO_EXTENSIONS else image_format(dst_path)
    if image is None and Path(dst_path).suffix.lower() not in VIDEO_EXTENSIONS:
        raise FormatError(f"{src_path} is a video: give -o NAME with one of {', '.join(VIDEO_EXTENSIONS)}, or "
                          "an image name for one file per frame (e.g. 'frames/%04d.exr')")
    if args.stmap:
        raise FormatError("--stmap applies to images; warp a video with --to SPEC")
    if args.exposure == "auto":
        raise FormatError("--exposure auto applies to images; give a number of stops for a video")
    check_output(dst_path, [src_path], args.overwrite)
    start, stop = getattr(args, "frames", None) or (0, None)
    from lenslab.io.budget import admit_clip

    admit_clip(src_path)
    info = probe_video(src_path)
    total = max(0, (info.frames if stop is None else min(stop, info.frames or stop)) - start)
    src = source_camera(args.source, {"path": src_path}, (info.height, info.width))
    from lenslab.warp.mirror import mirror_frames, mirror_source_pose, parse_flips, shown_camera

    source_flips = parse_flips(getattr(args, "source_flip", None), "hv", "--source-flip")
    true_src, src = src, mirror_source_pose(src, parse_flips(getattr(args, "flip", None)))
    size = args.size or default_output_size(args.to, src.lens)
    src = place_source(args.to, src, False, args.eye)  # (a video records no camera)
    dst = output_camera(args, src, size)
    if args.autoscale:
        dst = autoscale_camera(src, dst, args.autoscale, args.samples, args.quiet, args.verbose)
    show = not args.quiet and sys.stderr.isatty()
    if image is not None:
        shown = shown_camera(true_src, src, dst)  # the view each frame's pixels show, which it records
        return _to_files(src_path, dst_path, image, args, cache, (src, dst, info, shown), (start, stop, total),
                         source_flips, show)
    display = getattr(args, "display", None)
    if display:  # code values of an OpenColorIO display, tagged as that display
        from dataclasses import replace

        from lenslab.io.ocio import processor
        from lenslab.io.video import display_tags

        name = processor(display, args.view, args.colorspace, args.ocio)[1][0]
        primaries, transfer, matrix = display_tags(name)
        info = replace(info, primaries=primaries, transfer=transfer, matrix=matrix)
    from lenslab.io.video.codecs import check_encodes

    # a size the encoder of the clip's (or the display's) transfer refuses, H.265 for PQ/HLG in .mp4: before the output's
    # temporary is made and any frame decoded
    check_encodes(size, dst_path, getattr(args, "codec", None), info.curve, "--size")
    from lenslab.io.registry import formats
    from lenslab.jobs.stages import Look, develop

    clip = next(f for f in formats().values() if Path(dst_path).suffix.lower() in f.extensions)
    look = Look(exposure=args.exposure, display=display, view=args.view, colorspace=args.colorspace, ocio=args.ocio)
    whole = start == 0 and stop is None
    written = 0
    with atomic_write_path(dst_path, overwrite=args.overwrite) as tmp:
        plan = _maps_ahead(cache, src, dst)  # computed while the encoder and the decoder open
        writer = VideoWriter(tmp, info, codec=getattr(args, "codec", None), size=tuple(dst.size),
                             audio_from=src_path if whole and info.audio else None)
        open_encoder(writer.container, writer.stream)  # while the maps are made; a size it refuses: one error now
        with writer, _frame_bar(show, total, Path(src_path).name) as bar:
            # frames are converted to linear light where the plan reads
            window = None if source_flips else (lambda: plan().source_spans())
            # output frames reused in turn: the writer may still read `held` earlier ones (none when it takes each
            # frame to the encoder's planes as it is written)
            ring = [(np.empty((dst.size[1], dst.size[0], 3), np.float32),
                     np.empty((dst.size[1], dst.size[0]), np.float32)) for _ in range(1 + writer.held)]
            # decoded two frames ahead on a thread of its own; converted, warped and taken to the encoder's planes
            # here, each pass on every core; encoded on a thread of its own
            developed = display or look.always or float(args.exposure) != 0.0  # else the look is the identity
            for k, (_, frame) in enumerate(read_frames(src_path, start, stop, prefetch=2, window=window)):
                # Y'CbCr out: each band's rows go to the encoder's planes on the band's thread, while in cache
                rows = None if developed else writer.rows()
                # warped as a still image is (outside the view: black), with the plan made ahead
                out, _ = cache.warp_frame(mirror_frames(frame, src.lens, source_flips), src, dst,
                                          into=ring[k % len(ring)], on_band=rows, plan=plan())
                if developed:
                    out, _ = develop(out, {"display_encoded": True}, clip, look)  # exposure, or the display
                writer.write(out if rows is None else rows.finish(out), encoded=bool(display),
                             handover=True)  # not reused until encoded
                written += 1
                bar.update()
        if written == 0:
            raise FormatError(f"{src_path}: no frame in the range {start}:{'' if stop is None else stop}")
    _note_softening(args, plan())
    if info.audio and not whole:
        import warnings

        warnings.warn("the audio was left out: it is kept only when the whole clip is warped", UserWarning,
                      stacklevel=2)


def image_format(path):
    """The record of the image format a name asks for (by its extension), or None when it names none."""
    from lenslab.errors import FormatError
    from lenslab.io.registry import format_for_path, get

    try:
        fmt = get(format_for_path(path, None))
    except FormatError:
        return None
    return None if fmt.kind == "video" else fmt


def _to_files(src_path, dst_path, fmt, job, cache, cameras, frames, source_flips, show) -> None:
    """Every frame (of ``frames``: start, stop, total) warped from camera ``src`` to ``dst`` (``cameras``: src,
    dst, the clip's info and the camera each frame records, :func:`~lenslab.warp.mirror.shown_camera`) and written
    as an image of format record ``fmt``, developed as a still image is,
    numbered as in the clip; all or none."""
    from lenslab.errors import FormatError
    from lenslab.io.colour.gamut import WIDE_GAMUT, tallied
    from lenslab.io.video.colour import gamut_name
    from lenslab.jobs.frame_files import all_or_none, frame_output, note_frames
    from lenslab.jobs.warp.output import output_arrays, write_warped
    from lenslab.io.video import read_frames
    from lenslab.warp.mirror import mirror_frames

    src, dst, info, shown = cameras
    start, stop, total = frames
    # SDR frames are display light already (no tone curve for display outputs); PQ/HLG frames are HDR
    meta = {"format": "video", "display_encoded": not info.hdr, "sample_type": "uint", "camera": None,
            WIDE_GAMUT: gamut_name(info.primaries)}  # frames converted from P3 or BT.2020: clipped for display
    plan = _maps_ahead(cache, src, dst)
    window = None if source_flips else (lambda: plan().source_spans())

    def write_frames():
        written, pixels, first, last = 0, 0, None, None
        with _frame_bar(show, total, Path(src_path).name) as bar, tallied() as gamut:  # one note on the frames
            for i, frame in read_frames(src_path, start, stop, prefetch=2, window=window):
                # drawn into the channels of the one image written, developed and encoded in its memory
                into = output_arrays((dst.size[1], dst.size[0]), 3, fmt, job, meta, False)
                warped = list(cache.warp_frame(mirror_frames(frame, src.lens, source_flips), src, dst, into=into,
                                               plan=plan()))
                del into
                last = frame_output(dst_path, i, src_path, job.overwrite)
                write_warped(last, warped.pop(0), warped.pop(0), meta, fmt, job, shown,  # (the view the pixels show)
                             given_up=True)
                written, pixels, first = written + 1, dst.size[0] * dst.size[1], first or last
                bar.update()
        if written == 0:
            raise FormatError(f"{src_path}: no frame in the range {start}:{'' if stop is None else stop}")
        gamut.warn(str(dst_path), written, pixels)
        note_frames(written, first, last)
        _note_softening(job, plan())

    all_or_none(write_frames)


def _note_softening(job, plan) -> None:
    """The note of a clip warped with --antialias whose view shrinks the source nowhere (:mod:`lenslab.jobs.warp.output`)."""
    if job.antialias:
        from lenslab.jobs.warp.output import note_softening

        note_softening(job, plan)


def _maps_ahead(cache, src, dst):
    """Start computing the maps of ``src -> dst`` (``cache``'s plan) on a thread of their own; the function returned
    waits for them and gives the plan, or raises what went wrong there."""
    import threading

    box: dict = {}

    def work():
        try:
            plan = cache.plan(src, dst)
            plan.prepare()
            plan.source_spans()  # kept by the plan
            box["plan"] = plan
        except BaseException as exc:  # raised in the caller's thread
            box["error"] = exc

    # not a daemon: a run that ends before it waits (no frame in the range, a damaged first frame) lets it
    # finish before the interpreter goes, instead of aborting in the middle of native code
    thread = threading.Thread(target=work, daemon=False, name="lenslab-maps")
    thread.start()

    def plan():
        thread.join()
        if "error" in box:
            raise box["error"]
        return box["plan"]

    return plan


def _frame_bar(show: bool, total: int, name: str):
    """A progress bar by frames, or (not shown) a stand-in: tqdm's import is left to runs that show it."""
    if not show:
        from contextlib import nullcontext
        from types import SimpleNamespace

        return nullcontext(SimpleNamespace(update=lambda n=1: None))
    from tqdm import tqdm

    return tqdm(total=total or None, unit="frame", file=sys.stderr, leave=False, desc=name)
