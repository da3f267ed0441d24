"""What a video file declares, checked before FFmpeg decodes it: the top-level boxes of an MP4/MOV file
and a decoded frame's size and rate (the format's ``declare`` hook, :mod:`lenslab.io.budget`)."""

from __future__ import annotations

from lenslab.errors import FormatError


#: boxes of an ISO media file walked before FFmpeg sees it, at most
MAX_BOXES = 1 << 16
#: boxes inside boxes, at most (real files nest 8 or 9 deep: moov/trak/mdia/minf/stbl/stsd/...)
MAX_DEPTH = 32
#: boxes that hold only boxes (ISO 14496-12), by the bytes of their own fields before the first
#: (dref and stsd are full boxes with an entry count)
CONTAINERS = {b"moov": 0, b"trak": 0, b"mdia": 0, b"minf": 0, b"stbl": 0, b"edts": 0, b"dinf": 0, b"udta": 0,
              b"mvex": 0, b"moof": 0, b"traf": 0, b"mfra": 0, b"tref": 0, b"sinf": 0, b"schi": 0, b"dref": 8,
              b"stsd": 8}
#: tables (full boxes: version and flags, then an entry count) by the size of one entry
TABLES = {b"stts": 8, b"ctts": 8, b"stsc": 12, b"stco": 4, b"co64": 8, b"stss": 4, b"stps": 4, b"elst": 12,
          b"dref": 8, b"stsd": 8}


def _refuse(path, kind: bytes, pos: int, why: str) -> None:
    raise FormatError(f"{path}: the box {kind[:4]!r} at byte {pos} {why}; the file is truncated, damaged or hostile")


def _check_table(f, path, kind: bytes, pos: int, body: int, end: int) -> None:
    """An entry count against the bytes its box holds (``stsz``: when samples differ in size)."""
    import struct

    f.seek(body)
    head = f.read(12)
    if len(head) < 8:
        _refuse(path, kind, pos, "is too short for its table's header")
    version = head[0]
    if kind == b"stsz":
        if len(head) < 12:
            _refuse(path, kind, pos, "is too short for its table's header")
        fixed, count = struct.unpack(">II", head[4:12])
        need = 12 + (0 if fixed else 4 * count)
    else:
        count = struct.unpack(">I", head[4:8])[0]
        entry = 20 if kind == b"elst" and version == 1 else TABLES[kind]
        need = 8 + entry * count
    if body + need > end:
        _refuse(path, kind, pos, f"declares {count} entries, {need} bytes, in {end - body} bytes")


def _walk(f, path, start: int, end: int, depth: int, count: list, parent: bytes | None) -> None:
    import struct

    pos = start
    while pos + 8 <= end:
        f.seek(pos)
        head = f.read(16)
        n, kind = struct.unpack(">I4s", head[:8])
        header = 8
        if n == 1:  # a 64-bit size follows
            if len(head) < 16 or pos + 16 > end:
                _refuse(path, kind, pos, "has a 64-bit size cut off")
            n, header = struct.unpack(">Q", head[8:16])[0], 16
        elif n == 0:  # to the end of the file (or of the box that holds it)
            n = end - pos
        where = "the file" if parent is None else f"its parent box {parent!r}"
        if n < header:
            _refuse(path, kind, pos, f"has size {n}, which cannot advance")
        if pos + n > end:
            _refuse(path, kind, pos, f"has size {n}, which runs past the end of {where}")
        count[0] += 1
        if count[0] > MAX_BOXES:
            raise FormatError(f"{path}: more than {MAX_BOXES} boxes; the file is damaged or hostile")
        if kind == b"stsz" or kind in TABLES:
            _check_table(f, path, kind, pos, pos + header, pos + n)
        if kind in CONTAINERS:
            if depth >= MAX_DEPTH:
                _refuse(path, kind, pos, f"is nested more than {MAX_DEPTH} boxes deep")
            _walk(f, path, pos + header + CONTAINERS[kind], pos + n, depth + 1, count, kind)
        pos += n  # n >= 8: every step advances, so the walk ends


def check_boxes(path) -> None:
    """Walk an MP4/MOV file's boxes (ISO 14496-12: 32-bit size and type, size 1: a 64-bit size follows,
    size 0: to the end) into the boxes that hold boxes, before the demuxer sees them: a size that cannot
    advance or runs past the end of the file or of its parent box, nesting deeper than
    :data:`MAX_DEPTH`, more than :data:`MAX_BOXES` boxes, or a sample table (``stts``, ``stsc``,
    ``stsz``, ``stco``...) whose entry count needs more bytes than its box holds is refused. Only box
    headers and table counts are read (media data is skipped)."""
    import os

    size = os.path.getsize(path)
    with open(path, "rb") as f:
        _walk(f, path, 0, size, 0, [0], None)


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


__all__ = ["MAX_BOXES", "MAX_DEPTH", "check_boxes", "declare_video"]
