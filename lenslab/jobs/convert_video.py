"""``lenslab convert`` on video: a clip to one image file per frame (``NAME.000000.exr``, ..., or the frame
number where the name has ``%04d``), in linear light decoded as :mod:`lenslab.io.video` describes."""

from __future__ import annotations

import sys
from pathlib import Path

from lenslab.jobs.frame_files import frame_output, note_frames


def frames_to_files(src: str, dst: str, job) -> str:
    """Write every frame of ``src`` (or the range of the :class:`~lenslab.jobs.convert.ConvertJob` ``job``'s
    ``frames``) next to ``dst`` (named by :func:`~lenslab.jobs.frame_files.frame_path`), all or none
    (:func:`~lenslab.jobs.frame_files.all_or_none`); returns the first path."""
    from lenslab.jobs.frame_files import all_or_none

    return all_or_none(lambda: _frames(src, dst, job))


def _frames(src: str, dst: str, job) -> str:
    from tqdm import tqdm

    from lenslab.errors import FormatError
    from lenslab.io import write
    from lenslab.io.budget import admit_clip
    from lenslab.io.colour.gamut import tallied
    from lenslab.io.video import probe_video, read_frames

    admit_clip(src)
    info = probe_video(src)
    start, stop = job.frames or (0, None)
    meta = _clip_meta(info)
    first, last, written, pixels = None, None, 0, 0
    total = max(0, (min(stop, info.frames) if stop is not None and info.frames else (stop or info.frames)) - start)
    show = sys.stderr.isatty() and not job.quiet
    with tqdm(total=total or None, unit="frame", disable=not show, file=sys.stderr, leave=False,
              desc=Path(src).name) as bar, tallied() as gamut:  # colours outside sRGB: one note for the frames
        for i, frame in read_frames(src, start, stop):
            image, opts = job.develop(frame, meta)
            path = frame_output(dst, i, src, job.overwrite)
            write(path, image, format=job.to, overwrite=job.overwrite, **opts)
            first, last = first or str(path), str(path)
            written, pixels = written + 1, frame.shape[0] * frame.shape[1]
            bar.update()
    if first is None:
        raise FormatError(f"{src}: no frame in the range {start}:{'' if stop is None else stop}")
    gamut.warn(dst, written, pixels)
    note_frames(written, first, last)
    return first


#: --transfer of an image sequence written as video -> FFmpeg's (primaries, transfer, matrix) tags
TRANSFERS = {"bt709": (1, 1, 1), "pq": (9, 16, 9), "hlg": (9, 18, 9)}


def files_to_video(files: list[str], dst: str, options: dict) -> int:
    """Encode image files and clips (in the order given) as one clip at ``options["rate"]`` frames per second
    (None: the rate of the first input clip, else 24); returns the number of frames written.

    A clip among the inputs gives every one of its frames (those of ``options["frames"]``, ``(start, stop)``, when
    given), so a clip converted to a clip is re-encoded whole. ``bt709``: SDR, the tone curve (or ``--display``)
    first as for any display output (an SDR clip's frames hold display light already: no curve); ``pq``/``hlg``:
    linear light as it is (1.0 = 203 cd/m^2), BT.2020, 10-bit. Colours of wide-gamut frames outside the sRGB
    gamut are clipped per channel and counted over the clip, in one note.
    """
    from fractions import Fraction

    from tqdm import tqdm

    from lenslab.jobs.policy import check_output
    from lenslab.errors import FormatError
    from lenslab.atomic import atomic_write_path
    from lenslab.io.video import VideoInfo, VideoWriter

    from lenslab.io.registry import formats
    from lenslab.jobs.stages import Look, develop

    check_output(dst, [Path(f) for f in files], options["overwrite"])
    clip = next(f for f in formats().values() if Path(dst).suffix.lower() in f.extensions)  # the container's record
    look = Look(tone=options["tone"], exposure=options["exposure"],
                **{k: options.get(k) for k in ("display", "view", "colorspace", "ocio")})
    primaries, transfer, matrix = TRANSFERS[options.get("transfer") or "bt709"]
    hdr = transfer != 1
    show = sys.stderr.isatty() and not options.get("quiet")
    from lenslab.io.colour.gamut import tallied

    # colours outside the sRGB gamut: counted over every frame, one note for the clip
    rate = options.get("rate") or _first_rate(files) or 24
    audio = _audio_kept(files, options.get("frames"))
    import warnings

    from lenslab.jobs.stages import AutoExposureNote

    with atomic_write_path(dst, overwrite=options["overwrite"]) as tmp, tallied() as gamut, warnings.catch_warnings():
        warnings.filterwarnings("ignore", category=AutoExposureNote)  # (a line per frame would bury the others)
        writer = None
        try:
            for f, image, meta in tqdm(_inputs_frames(files, options.get("frames")), unit="frame",
                                       disable=not show, file=sys.stderr, leave=False):
                if not hdr:  # SDR: the look of any display output (the tone curve, or --display)
                    image, _ = develop(image, meta, clip, look)
                if image.shape[2] == 1:
                    image = image.repeat(3, axis=2)
                if writer is None:
                    h, w = image.shape[:2]
                    info = VideoInfo(w, h, Fraction(str(rate)), len(files), "", "", primaries, transfer, matrix, 1)
                    from lenslab.io.video.codecs import check_encodes, open_encoder
                    from lenslab.jobs.warp.video import is_video

                    try:  # a size the encoder refuses: one line now, before the clip's file is made (or it is closed)
                        if is_video(f):  # (a clip's size is not convert's to give: warp's --size is the way out)
                            check_encodes((w, h), tmp, options.get("codec"), info.curve, "clip")
                        writer = VideoWriter(tmp, info, codec=options.get("codec"), audio_from=audio)
                        open_encoder(writer.container, writer.stream)
                    except FormatError as exc:
                        writer = None
                        raise FormatError(f"{f}: {exc}") from None
                elif image.shape[:2] != (writer.info.height, writer.info.width):
                    raise FormatError(f"{f}: {image.shape[1]}x{image.shape[0]} differs from the first frame's "
                                      f"{writer.info.width}x{writer.info.height}; a clip has one size")
                writer.write(image[..., :3])
        finally:
            if writer is not None:
                writer.close()
    if writer is None:
        return 0
    gamut.warn(dst, writer.count, writer.info.width * writer.info.height)
    return writer.count


def _audio_kept(files: list[str], frames) -> str | None:
    """The clip whose audio packets are copied into the output: the one input, when it is a clip with audio
    written whole (as ``lenslab warp`` keeps it); None otherwise, with a note when a clip's audio is left out."""
    from lenslab.jobs.warp.video import is_video

    clips = [f for f in files if is_video(f)]
    if not clips:
        return None
    from lenslab.io.video import probe_video

    heard = [f for f in clips if probe_video(f).audio]
    if not heard:
        return None
    if len(files) == 1 and (frames is None or tuple(frames) == (0, None)):
        return heard[0]
    import warnings

    warnings.warn(f"{heard[0]}: the audio was left out: it is kept only when one whole clip is converted",
                  UserWarning, stacklevel=3)
    return None


def _first_rate(files: list[str]):
    """The frame rate of the first clip among ``files`` (a Fraction), or None when they are all still images."""
    from lenslab.jobs.warp.video import is_video

    clip = next((f for f in files if is_video(f)), None)
    if clip is None:
        return None
    from lenslab.io.video import probe_video

    return probe_video(clip).rate or None


def _inputs_frames(files: list[str], frames=None):
    """``(path, linear image, meta)`` of every frame a clip made of ``files`` gets: an image file's one, each
    frame of a clip (within ``frames``, ``(start, stop)``), read as :func:`frames_to_files` reads them."""
    from lenslab.io import read
    from lenslab.jobs.warp.video import is_video

    for f in files:
        if not is_video(f):
            image, meta = read(f)
            yield f, image, meta
            continue
        from lenslab.errors import FormatError
        from lenslab.io.budget import admit_clip
        from lenslab.io.video import probe_video, read_frames

        admit_clip(f)
        meta = _clip_meta(probe_video(f))
        start, stop = frames or (0, None)
        count = 0
        for _, frame in read_frames(f, start, stop):
            count += 1
            yield f, frame, meta
        if not count:
            raise FormatError(f"{f}: no frame in the range {start}:{'' if stop is None else stop}")


def _clip_meta(info) -> dict:
    """What a decoded frame of a clip is (``info``: its :class:`~lenslab.io.video.clips.VideoInfo`): SDR frames hold
    display light already (no tone curve for display outputs); PQ/HLG frames are HDR; colours of a P3 or BT.2020
    clip are clipped for display."""
    from lenslab.io.colour.gamut import WIDE_GAMUT
    from lenslab.io.video.colour import gamut_name

    return {"format": "video", "display_encoded": not info.hdr, "sample_type": "uint", "camera": None,
            WIDE_GAMUT: gamut_name(info.primaries)}
