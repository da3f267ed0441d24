"""Video (MP4, MOV, MKV) through PyAV: ``read`` gives the first frame in linear light; whole clips go
through :mod:`lenslab.io.video` (``lenslab warp`` and ``lenslab convert`` use it)."""

from __future__ import annotations

from lenslab.io.codecs import VIDEO_EXTENSIONS
from lenslab.io.plugin import Format


def _magic(head: bytes) -> bool:
    return head[4:8] == b"ftyp" or head.startswith(b"\x1a\x45\xdf\xa3")


def _read(path, selector=None):
    from lenslab.io.video import probe_video, read_frames

    info = probe_video(path)
    for _, frame in read_frames(path, 0, 1):
        meta = {"format": "video", "bit_depth": 10 if "10" in info.pixel_format else 8, "sample_type": "uint",
                "channels": ["R", "G", "B"], "display_encoded": True,
                "attributes": {"codec": info.codec, "frames": info.frames, "frame_rate": str(info.rate),
                               "transfer": info.curve, "note": "the first frame"}}
        return frame, meta
    from lenslab.errors import FormatError

    raise FormatError(f"{path}: the video holds no frame")



def _declare(path, **_):
    from lenslab.io.video import declare_video

    return declare_video(path)

FORMATS = (Format(
    name="video", title="video (MP4, MOV, MKV)", extensions=VIDEO_EXTENSIONS, magic=_magic,
    hdr=False, alpha=False, channels=(3,), bit_depths=(8, 10), sample_types=("uint",), read=_read, declare=_declare,
    note="H.264, H.265 10-bit, ProRes, FFV1; SDR, PQ and HLG decoded to linear; warp and convert take whole clips",
    kind="video"),)
