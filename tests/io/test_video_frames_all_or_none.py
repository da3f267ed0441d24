"""`lenslab convert clip -o frames/` writes all the frames or none: a clip whose frame size changes
mid-stream fails at the first frame of another size (PyAV's decoding says which) and leaves the output
folder as it was, with no frame written before the failure and no temporary; frames already there (with
--overwrite) keep their bytes."""

from __future__ import annotations

import subprocess
import sys

import pytest

pytest.importorskip("av")

from tests.io.test_video_size_change import resized  # noqa: E402,F401  (the clip that changes size)


def _convert(clip, out, *extra):
    return subprocess.run([sys.executable, "-m", "lenslab", "convert", str(clip), "--to", "png", "-o", str(out) + "/",
                           *extra], capture_output=True, text=True)


def test_a_failed_clip_leaves_no_frame(resized, tmp_path):  # noqa: F811
    clip, _, _, n = resized
    assert n == 6  # PyAV decodes six frames of the first size before the failure
    out = tmp_path / "frames"
    out.mkdir()
    run = _convert(clip, out)
    assert run.returncode == 1
    assert f"frame {n} " in run.stderr
    assert sorted(p.name for p in out.iterdir()) == []  # neither the six frames nor a temporary


def test_frames_already_there_keep_their_bytes(resized, tmp_path):  # noqa: F811
    clip, _, _, n = resized
    out = tmp_path / "frames"
    first = _convert(clip, out, "--frames", f"0:{n}")
    assert first.returncode == 0, first.stderr
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    assert len(before) == n
    for p in out.iterdir():  # mark them: a rewrite would change the bytes
        p.write_bytes(before[p.name] + b"kept")
    run = _convert(clip, out, "--overwrite")
    assert run.returncode == 1
    assert {p.name: p.read_bytes() for p in out.iterdir()} == {k: v + b"kept" for k, v in before.items()}


def test_a_whole_range_is_renamed_at_the_end(resized, tmp_path):  # noqa: F811
    clip, _, _, n = resized
    out = tmp_path / "frames"
    run = _convert(clip, out, "--frames", f"0:{n}")
    assert run.returncode == 0, run.stderr
    names = sorted(p.name for p in out.iterdir())
    assert names == [f"ab.{i:06d}.png" for i in range(n)]  # every frame, no temporary


def test_a_printf_name_numbers_the_frames_and_fails_whole(resized, tmp_path):  # noqa: F811
    clip, _, _, n = resized
    out = tmp_path / "frames"
    out.mkdir()
    pattern = str(out / "f_%04d.png")
    run = subprocess.run([sys.executable, "-m", "lenslab", "convert", str(clip), "--to", "png", "--frames", f"2:{n}",
                          "-o", pattern], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    # the clip's own frame numbers (as --frames counts them), printf's %04d
    assert sorted(p.name for p in out.iterdir()) == ["f_%04d.png" % i for i in range(2, n)]
    again = subprocess.run([sys.executable, "-m", "lenslab", "convert", str(clip), "--to", "png", "-o",
                            str(tmp_path / "g_%d.png")], capture_output=True, text=True)
    assert again.returncode == 1
    assert not list(tmp_path.glob("g_*")) and not list(tmp_path.glob(".g_*"))
