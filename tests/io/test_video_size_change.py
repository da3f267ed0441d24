"""A clip whose frame size changes mid-stream fails in one line naming the first frame of another size, for
every command that reads clips. The clip is two H.264 streams of different sizes joined (as MPEG-TS files
join) and put in Matroska; the frame number expected is where PyAV's own decoding first gives another size."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

av = pytest.importorskip("av")


def _ts(path, w, h, n, level):
    with av.open(str(path), "w", format="mpegts") as c:
        s = c.add_stream("libx264", rate=10)
        s.width, s.height, s.pix_fmt = w, h, "yuv420p"
        for k in range(n):
            frame = av.VideoFrame.from_ndarray(np.full((h, w, 3), level + 10 * k, np.uint8), format="rgb24")
            for p in s.encode(frame):
                c.mux(p)
        for p in s.encode():
            c.mux(p)


@pytest.fixture(scope="module")
def resized(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("clip")
    _ts(tmp / "a.ts", 64, 32, 6, 40)
    _ts(tmp / "b.ts", 48, 32, 4, 120)
    joined = tmp / "ab.ts"
    joined.write_bytes((tmp / "a.ts").read_bytes() + (tmp / "b.ts").read_bytes())
    clip = tmp / "ab.mkv"
    with av.open(str(joined)) as src, av.open(str(clip), "w") as dst:
        si = src.streams.video[0]
        so = dst.add_stream_from_template(si)
        offset, last = 0, None
        for packet in src.demux(si):
            if packet.dts is None:
                continue
            if last is not None and packet.dts + offset <= last:  # the second stream's clock starts again
                offset = last + (packet.duration or 9000) - packet.dts + 2 * 9000  # (room for its reordering)
            packet.dts += offset
            packet.pts += offset
            last = packet.dts
            packet.stream = so
            dst.mux(packet)
    with av.open(str(clip)) as c:  # PyAV's reading: the declared size and the first frame of another
        s = c.streams.video[0]
        declared = (s.codec_context.width, s.codec_context.height)
        sizes = [(f.width, f.height) for f in c.decode(s)]
    first_other = next(i for i, size in enumerate(sizes) if size != declared)
    return clip, declared, sizes[first_other], first_other


@pytest.mark.parametrize("command", [["convert", "--to", "png"], ["warp", "--to", "fisheye:fov=180", "--size", "32x32"]])
def test_one_line_names_the_frame(resized, tmp_path, command):
    clip, (w, h), (w2, h2), n = resized
    assert n == 6  # the second stream starts after the first's six frames
    out = tmp_path / ("frames/" if command[0] == "convert" else "out.mp4")
    run = subprocess.run([sys.executable, "-m", "lenslab", command[0], str(clip), *command[1:], "-o", str(out)],
                         capture_output=True, text=True)
    assert run.returncode == 1
    lines = run.stderr.splitlines()
    assert len(lines) == 1, lines
    assert lines[0].startswith(f"lenslab {command[0]}: error: {clip}: frame {n} ")
    assert f"{w2} x {h2}, not {w} x {h}" in lines[0]
    if command[0] == "warp":
        assert not out.exists()  # no half-written clip


def test_frames_before_the_change_still_convert(resized, tmp_path):
    clip, _, _, n = resized
    run = subprocess.run([sys.executable, "-m", "lenslab", "convert", str(clip), "--to", "png", "--frames", f"0:{n}",
                          "-o", str(tmp_path / "f") + "/"], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert len(list((tmp_path / "f").glob("*.png"))) == n
