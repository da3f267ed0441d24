"""What a video file declares, checked before FFmpeg decodes it: the top-level boxes of an MP4/MOV file
and a decoded frame's size and rate (the format's ``declare`` hook, :mod:`lenslab.io.budget`)."""

from __future__ import annotations

from lenslab.errors import FormatError


#: top-level boxes of an ISO media file walked before FFmpeg sees it
MAX_BOXES = 1 << 16


def check_boxes(path) -> None:
    """Walk an MP4/MOV file's top-level boxes (ISO 14496-12: 32-bit size and type, size 1: a 64-bit size
    follows, size 0: to the end of the file): a size that cannot advance or runs past the end, or a
    runaway count of boxes, is refused before the demuxer loops on it."""
    import os
    import struct

    size = os.path.getsize(path)
    with open(path, "rb") as f:
        pos, boxes = 0, 0
        while pos + 8 <= size:
            f.seek(pos)
            n, kind = struct.unpack(">I4s", f.read(8))
            if n == 1:
                if pos + 16 > size:
                    break
                n = struct.unpack(">Q", f.read(8))[0]
            elif n == 0:
                break
            if n < 8 or pos + n > size:
                raise FormatError(f"{path}: the box {kind[:4]!r} at byte {pos} has size {n}, which "
                                  f"{'cannot advance' if n < 8 else 'runs past the end of the file'}; the file is "
                                  "truncated or damaged")
            pos += n
            boxes += 1
            if boxes > MAX_BOXES:
                raise FormatError(f"{path}: more than {MAX_BOXES} top-level boxes; the file is damaged or hostile")


def declare_video(path):
    """:class:`lenslab.io.budget.Declared` of one decoded frame; the frame rate must be finite and positive."""
    import math

    from lenslab.io.budget import Declared

    with open(path, "rb") as f:
        head = f.read(8)
    if head[4:8] == b"ftyp":
        check_boxes(path)
    from lenslab.io.video import probe_video

    info = probe_video(path)
    rate = float(info.rate) if info.rate else float("nan")
    if not (math.isfinite(rate) and 0 < rate <= 1000):
        raise FormatError(f"{path}: the video's frame rate {str(info.rate)[:20]} is not a positive rate up to 1000 "
                          "fps; the file is damaged")
    return Declared(int(info.width), int(info.height), 3)


__all__ = ["MAX_BOXES", "check_boxes", "declare_video"]
