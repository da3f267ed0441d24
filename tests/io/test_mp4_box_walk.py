"""The box walk of MP4/MOV files (lenslab.io.video.layout.check_boxes) before FFmpeg sees them: clips
written by PyAV (FFmpeg's muxers: MP4, MOV, fragmented MP4) pass; nesting without end, a box larger
than its parent, a box that cannot advance and sample tables that declare more entries than their box
holds are refused by ``lenslab convert`` in one line naming the file, in a subprocess under an
address-space limit, with nothing written."""

from __future__ import annotations

import struct
import sys

import numpy as np
import pytest

from lenslab.io.video.layout import MAX_DEPTH, check_boxes
from tests.hostile_run import run

av = pytest.importorskip("av")


def _clip(path, options=None, frames=3):
    with av.open(str(path), "w", options=options or {}) as clip:
        stream = clip.add_stream("libx264", rate=24)
        stream.width, stream.height, stream.pix_fmt = 64, 48, "yuv420p"
        for i in range(frames):
            frame = av.VideoFrame.from_ndarray(np.full((48, 64, 3), 40 * i, np.uint8), format="rgb24")
            for packet in stream.encode(frame):
                clip.mux(packet)
        for packet in stream.encode():
            clip.mux(packet)
    return path


def _boxes(data: bytes, start=0, end=None, inside=(b"moov", b"trak", b"mdia", b"minf", b"stbl")):
    """(type, offset, size) of every box on the path moov/trak/mdia/minf/stbl, as ISO 14496-12 lays them."""
    end = len(data) if end is None else end
    pos = start
    while pos + 8 <= end:
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        yield kind, pos, n
        if kind in inside:
            yield from _boxes(data, pos + 8, pos + n, inside)
        pos += n


def _find(data: bytes, kind: bytes) -> tuple[int, int]:
    return next((pos, n) for k, pos, n in _boxes(data) if k == kind)


@pytest.mark.parametrize("name,options", [("a.mp4", None), ("a.mov", None),
                                          ("f.mp4", {"movflags": "frag_keyframe+empty_moov"})])
def test_clips_that_ffmpeg_writes_pass_the_walk(tmp_path, name, options):
    path = _clip(tmp_path / name, options)
    check_boxes(path)
    with av.open(str(path)) as clip:  # FFmpeg reads them: three frames
        assert sum(1 for _ in clip.decode(video=0)) == 3


def _deep(data: bytes) -> bytes:
    """moov replaced by moov/trak/trak/... nested MAX_DEPTH + 8 deep (sizes consistent)."""
    pos, n = _find(data, b"moov")
    levels = MAX_DEPTH + 8
    nest = b""
    for i in range(levels):
        nest = struct.pack(">I4s", 8 + len(nest), b"trak" if i else b"stbl") + nest
    nest = struct.pack(">I4s", 8 + len(nest), b"moov") + nest
    return data[:pos] + nest + data[pos + n:]


def _child_past_parent(data: bytes) -> bytes:
    pos, _ = _find(data, b"trak")
    moov, moov_n = _find(data, b"moov")
    grown = moov + moov_n - pos + 16  # ends 16 bytes past moov (the file goes on: mdat follows or precedes)
    out = bytearray(data)
    out[pos:pos + 4] = struct.pack(">I", grown)
    return bytes(out) + bytes(32)


def _cannot_advance(data: bytes) -> bytes:
    pos, _ = _find(data, b"mdia")
    out = bytearray(data)
    out[pos:pos + 4] = struct.pack(">I", 4)
    return bytes(out)


def _table(kind: bytes, at: int, value: int):
    def mutate(data: bytes) -> bytes:
        pos, _ = _find(data, kind)
        out = bytearray(data)
        out[pos + at:pos + at + 4] = struct.pack(">I", value)
        return bytes(out)

    return mutate


HOSTILE = {
    "nested_too_deep": (_deep, "deep"),
    "child_past_its_parent": (_child_past_parent, "parent box"),
    "size_that_cannot_advance": (_cannot_advance, "cannot advance"),
    "stsz_count_2e9": (_table(b"stsz", 16, 2_000_000_000), "entries"),
    "stco_count_2e9": (_table(b"stco", 12, 2_000_000_000), "entries"),
    "stsc_count_2e9": (_table(b"stsc", 12, 2_000_000_000), "entries"),
}


@pytest.mark.parametrize("name", sorted(HOSTILE))
def test_hostile_boxes_are_refused_in_one_line(tmp_path, name):
    mutate, cause = HOSTILE[name]
    valid = _clip(tmp_path / "valid.mp4").read_bytes()
    path = tmp_path / f"{name}.mp4"
    path.write_bytes(mutate(valid))
    out = tmp_path / "out"
    out.mkdir()
    done = run([sys.executable, "-m", "lenslab", "convert", str(path), "--to", "exr", "-o", str(out)])
    assert done.returncode == 1, done.stderr[-500:]
    assert "Traceback" not in done.stderr
    lines = [line for line in done.stderr.splitlines() if line.strip()]
    named = [line for line in lines if str(path) in line]
    assert len(named) == 1 and cause in named[0], lines
    assert list(out.iterdir()) == []
