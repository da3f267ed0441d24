"""Video (MP4, MOV, MKV) through PyAV: ``read`` gives the first frame in linear light; whole clips go
through :mod:`lenslab.io.video` (``lenslab warp`` and ``lenslab convert`` use it)."""

from __future__ import annotations

from lenslab.io.video.codecs import VIDEO_EXTENSIONS
from lenslab.io.plugin import Format


def _magic(head: bytes) -> bool:
    from lenslab.io.formats.heif import is_heif  # an ISO base media file too: HEIF still images are not clips

    return (head[4:8] == b"ftyp" and not is_heif(head)) or head.startswith(b"\x1a\x45\xdf\xa3")


class FirstFrameWarning(UserWarning):
    """A clip of several frames read as one image (``lenslab tonemap clip.mp4``, ``lenslab diff``): its first frame is
    the image, and the note says so and names the commands that take every frame. ``command_line``: without the
    path."""


def _read(path, selector=None):
    from lenslab.io.video import probe_video, read_frames

    info = probe_video(path)
    frames = [frame for _, frame in read_frames(path, 0, 1 if info.frames == 1 else 2)]  # a second: a clip of several
    if not frames:
        from lenslab.errors import FormatError

        raise FormatError(f"{path}: the video holds no frame")
    if len(frames) > 1:
        import warnings

        count = f"a clip of {info.frames} frames" if info.frames > 1 else "a clip of several frames"
        note = f"{count}: its first frame read, as one image ('lenslab convert' and 'lenslab warp' take every frame)"
        warning = FirstFrameWarning(f"{path}: {note}")
        warning.command_line = note
        warnings.warn(warning, stacklevel=3)
    meta = {"format": "video", "bit_depth": 10 if "10" in info.pixel_format else 8, "sample_type": "uint",
            "channels": ["R", "G", "B"], "display_encoded": True,
            "attributes": {"codec": info.codec, "frames": info.frames, "frame_rate": str(info.rate),
                           "transfer": info.curve, "note": "the first frame"}}
    return frames[0], meta


def _declare(path, **_):
    from lenslab.io.video.layout import declare_video

    return declare_video(path)


# FFmpeg's colour enums (libavutil/pixfmt.h) by the names ffprobe prints
_PRIMARIES = {1: "bt709", 2: "unspecified", 5: "bt470bg", 6: "smpte170m", 9: "bt2020", 12: "smpte432 (P3-D65)"}
_TRANSFER = {1: "bt709", 2: "unspecified", 6: "smpte170m", 13: "iec61966-2-1 (sRGB)", 14: "bt2020-10",
             15: "bt2020-12", 16: "smpte2084 (PQ)", 18: "arib-std-b67 (HLG)"}
_MATRIX = {0: "gbr", 1: "bt709", 2: "unspecified", 5: "bt470bg", 6: "smpte170m", 9: "bt2020nc", 10: "bt2020c"}
_RANGE = {0: "unspecified", 1: "tv (limited)", 2: "pc (full)"}


def _tag(names: dict, value) -> str:
    return names.get(int(value), str(int(value)))


def _probe(path) -> dict:
    """Container, duration and every stream (PyAV): a video stream's size, pixel format, rate, frame count
    and colour tags; an audio stream's rate and channels."""
    import av

    from lenslab.errors import FormatError, cause

    try:
        container = av.open(str(path))
    except av.error.FFmpegError as exc:
        raise FormatError(f"{path}: FFmpeg cannot open it as a video ({cause(exc)})") from None
    with container:
        streams = []
        for s in container.streams:
            d = {"index": s.index, "kind": s.type, "codec": s.codec_context.name}
            if s.type == "video":
                cc = s.codec_context
                d.update({"width": cc.width, "height": cc.height, "pixel_format": cc.pix_fmt,
                          "frame_rate": str(s.average_rate), "frames": int(s.frames),
                          "colour_primaries": _tag(_PRIMARIES, cc.color_primaries),
                          "transfer": _tag(_TRANSFER, cc.color_trc), "matrix": _tag(_MATRIX, cc.colorspace),
                          "range": _tag(_RANGE, cc.color_range)})
            elif s.type == "audio":
                d.update({"sample_rate": s.codec_context.sample_rate, "channels": s.codec_context.channels})
            streams.append(d)
        return {"container": container.format.name,
                "duration_s": None if container.duration is None else container.duration / 1e6,
                "streams": streams}


FORMATS = (Format(
    name="video", title="video (MP4, MOV, MKV)", extensions=VIDEO_EXTENSIONS, magic=_magic,
    hdr=False, alpha=False, channels=(3,), bit_depths=(8, 10), sample_types=("uint",), read=_read, declare=_declare, probe=_probe,
    note="H.264, H.265 10-bit, ProRes, FFV1; SDR, PQ and HLG decoded to linear; warp and convert read and write "
         "whole clips (--codec, --transfer)",
    kind="video"),)
