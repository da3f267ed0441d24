"""H.265 of small frames never kills the process: x265's CU-tree corrupts the heap or segfaults on some small
frames (34 x 32, 48 x 64, 36 x 36 of noise, several frames), and frames under 16 pixels x265 refuses. Each size
runs as its own command (a crash must not take the test run down); none may end by a signal. Expected values:
the width, height and frame count FFmpeg (through PyAV) decodes from each clip written; for the refused sizes,
x265's own refusal to open (PyAV, no lenslab), and one error line with exit status 1."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

av = pytest.importorskip("av")

import lenslab  # noqa: E402
from tests.io.test_video_encoder_open import encoder_opens  # noqa: E402

FRAMES = 5
#: written: the sizes x265's CU-tree crashed on (the first four), and neighbours that always encoded
WRITTEN = [(34, 32), (48, 64), (34, 64), (36, 36), (40, 48), (46, 34), (32, 64), (64, 34), (62, 62), (16, 16)]
REFUSED = [(14, 64), (64, 14), (8, 8)]


@pytest.fixture(scope="module", autouse=True)
def _has_x265():
    if "libx265" not in av.codecs_available:
        pytest.skip("this FFmpeg has no libx265")


def _noise(folder, width, height, frames=FRAMES):
    folder.mkdir()
    for i in range(frames):
        lenslab.write(folder / f"f{i:02d}.exr", np.random.default_rng(i).random((height, width, 3)).astype(np.float32))
    return folder / "*.exr"


def _decoded(path):
    with av.open(str(path)) as c:
        codec = c.streams.video[0].codec_context.name
        frames = [f for f in c.decode(video=0)]
    return frames[0].width, frames[0].height, len(frames), codec


def _lenslab(*args):
    run = subprocess.run([sys.executable, "-m", "lenslab", *map(str, args)], capture_output=True, text=True)
    assert run.returncode >= 0, f"killed by signal {-run.returncode}: {run.stderr[-400:]}"
    return run


@pytest.fixture(scope="module")
def noise_clip(tmp_path_factory):
    """A lossless (FFV1) clip of noise, the source of the warps."""
    where = tmp_path_factory.mktemp("clip")
    out = where / "noise.mkv"
    assert _lenslab("convert", _noise(where / "frames", 128, 64), "--to", "mkv", "-o", out, "-q").returncode == 0
    return out


@pytest.mark.parametrize("transfer", [None, "pq"])
@pytest.mark.parametrize("size", WRITTEN[:4])
def test_convert_of_small_frames_to_h265(tmp_path, size, transfer):
    w, h = size
    out = tmp_path / "clip.mp4"
    pick = ["--transfer", "pq"] if transfer else ["--codec", "h265"]  # PQ picks H.265 in .mp4
    run = _lenslab("convert", _noise(tmp_path / "frames", w, h), "--to", "mp4", "-o", out, *pick)
    assert run.returncode == 0, run.stderr
    assert _decoded(out) == (w, h, FRAMES, "hevc")


@pytest.mark.parametrize("size", WRITTEN)
def test_warp_into_small_h265_frames(tmp_path, noise_clip, size):
    w, h = size
    out = tmp_path / "warped.mp4"
    run = _lenslab("warp", noise_clip, "-o", out, "--to", "equirect", "--size", f"{w}x{h}", "--codec", "h265", "-q")
    assert run.returncode == 0, run.stderr
    assert _decoded(out) == (w, h, FRAMES, "hevc")


@pytest.mark.parametrize("size", REFUSED)
def test_sizes_x265_refuses_are_one_line(tmp_path, noise_clip, size):
    w, h = size
    assert not encoder_opens("libx265", "yuv420p10le", w, h, str(tmp_path / "probe.mp4"))
    assert encoder_opens("libx265", "yuv420p10le", 16, 16, str(tmp_path / "probe.mp4"))
    (tmp_path / "probe.mp4").unlink(missing_ok=True)
    expected = (f"the libx265 encoder (--codec h265) encodes frames of at least 16 x 16, not {w} x {h}: give frames "
                f"of {max(w, 16)} x {max(h, 16)} or larger, or --codec h264")
    # warp's --size is on the command line: a usage error (exit 2) naming the size to give, before the clip is read
    # (tests/io/test_video_x265_min_size.py); convert's frames bring their size: a failed input (exit 1), before the
    # clip's file is made
    usage = f"--size {w}x{h}: the libx265 encoder (--codec h265) encodes frames of at least 16 x 16; give --size"
    warp = _lenslab("warp", noise_clip, "-o", tmp_path / "w.mp4", "--to", "equirect", "--size", f"{w}x{h}",
                    "--codec", "h265")
    convert = _lenslab("convert", _noise(tmp_path / "frames", w, h, 2), "--to", "mp4", "-o", tmp_path / "c.mp4",
                       "--codec", "h265")
    for run, command, code, said in ((warp, "warp", 2, usage), (convert, "convert", 1, expected)):
        [line] = run.stderr.strip().splitlines()
        assert run.returncode == code and line.startswith(f"lenslab {command}: error: ") and said in line, line
    assert sorted(p.name for p in tmp_path.iterdir()) == ["frames"]  # no output, no temporary
