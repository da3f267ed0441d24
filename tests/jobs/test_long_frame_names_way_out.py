"""A clip written as one image per frame is named NAME.000042.EXT after the clip (or after -o): a clip whose name
fits but whose frames' names would pass 255 bytes (the frame number's 7 bytes added) is refused in one line that
names the way out, the frames named by their number alone (-o 'DIR/%06d.exr'), before any frame is decoded; that
way writes every frame FFmpeg (through PyAV) decodes from the clip."""

from __future__ import annotations

import shutil
import subprocess

import pytest

from lenslab.cli.main import main

av = pytest.importorskip("av")


@pytest.fixture
def long_clip(tmp_path):
    if shutil.which("ffmpeg") is None:
        pytest.skip("no ffmpeg")
    clip = tmp_path / ("ü" * 124 + ".mp4")  # 248 + 4 bytes: a name that fits
    subprocess.run(["ffmpeg", "-v", "error", "-y", "-f", "lavfi", "-i", "testsrc2=s=64x32:r=10", "-t", "0.3",
                    "-pix_fmt", "yuv420p", str(clip)], check=True)
    with av.open(str(clip)) as c:
        frames = sum(1 for _ in c.decode(video=0))
    return clip, frames


@pytest.mark.parametrize("command", ["convert", "warp"])
def test_frames_named_too_long_are_told_the_way_out(tmp_path, capsys, long_clip, command):
    clip, frames = long_clip
    out = tmp_path / "frames"
    if command == "warp":  # a clip to image files: -o names them (a folder alone would take a clip)
        extra, first = ["--to", "equirect", "--size", "64x32"], f"{out}/{'ü' * 124}.exr"
    else:  # convert to a folder: the frames are named after the clip
        extra, first = ["--to", "exr"], f"{out}/"
    assert main([command, str(clip), "-o", first, *extra]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "its name is too long: 259 bytes" in err, err
    advice = f"-o '{out}/%06d.exr'"
    assert advice in err, err
    assert not out.exists() or not any(out.iterdir())
    assert main([command, str(clip), "-o", f"{out}/%06d.exr", *extra, "-q"]) == 0
    assert sorted(p.name for p in out.iterdir()) == [f"{i:06d}.exr" for i in range(frames)]
