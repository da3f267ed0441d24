"""Output names up to the file system's limit (255 bytes: Linux's NAME_MAX, asked of the kernel with
``os.pathconf``) are written by convert, warp and a clip's warp, ASCII or UTF-8 with two-, three- and four-byte
characters: the temporary and the folder's probe fit in 255 bytes whatever the output's name, and the kernel's
refusal (ENAMETOOLONG) of any longer name is the outside judge that they do. A name over 255 bytes is one line
saying its name is too long (exit 1, as the other "cannot be written" refusals). The sweep of ``--skip-existing``
finds the temporary a killed run left for a 250-byte name, and :func:`lenslab.atomic.temporaries` tells apart
those of two long names that begin alike."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
from pathlib import Path

import cv2
import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import write

HANG_GUARD = 300  # seconds: only against a child that would otherwise wait forever on a broken build


def _name(total: int, suffix: str, char: str) -> str:
    """A file name of exactly ``total`` bytes in UTF-8: ``char`` repeated, padded with ASCII, then ``suffix``."""
    room = total - len(suffix.encode())
    body = char * (room // len(char.encode()))
    body += "a" * (room - len(body.encode()))
    name = body + suffix
    assert len(name.encode("utf-8")) == total
    return name


@pytest.fixture(autouse=True)
def _name_max(tmp_path):
    assert os.pathconf(tmp_path, "PC_NAME_MAX") == 255  # the kernel's limit these names are measured against


def _image(path: Path) -> np.ndarray:
    rng = np.random.default_rng(5)
    image = rng.random((16, 32, 3), dtype=np.float32)
    write(path, image)
    return image


CASES = [(n, c) for n in (200, 250, 255) for c in ("a", "é", "中", "🙂")]


@pytest.mark.parametrize("total, char", CASES)
def test_convert_writes_a_long_name(tmp_path, total, char):
    src = tmp_path / "in.exr"
    image = _image(src)
    out = tmp_path / _name(total, ".png", char)
    assert main(["convert", str(src), "-o", str(out), "--tone", "clamp", "-q"]) == 0
    assert sorted(os.listdir(tmp_path)) == sorted(["in.exr", out.name])  # the name as given; no temporary left
    png = cv2.imread(os.fsdecode(os.fsencode(out)), cv2.IMREAD_UNCHANGED)  # OpenCV reads what was written
    assert png.shape == (16, 32, 3)
    # the clamp curve, sRGB-encoded 8-bit: OpenCV's BGR codes are the sRGB encoding of the (clipped) values
    srgb = np.where(image <= 0.0031308, 12.92 * image, 1.055 * np.power(image, 1 / 2.4) - 0.055)
    assert np.abs(png[..., ::-1].astype(np.float64) - srgb * 255).max() <= 1.0  # a code's rounding (+ dither)


@pytest.mark.parametrize("total, char", [(200, "中"), (250, "a"), (255, "é"), (255, "🙂")])
def test_warp_writes_a_long_name(tmp_path, total, char):
    src = tmp_path / "in.exr"
    _image(src)
    out = tmp_path / _name(total, ".exr", char)
    assert main(["warp", str(src), "-o", str(out), "--from", "equirect", "--to", "equirect", "-q"]) == 0
    assert sorted(os.listdir(tmp_path)) == sorted(["in.exr", out.name])
    import OpenEXR

    assert OpenEXR.File(str(out)).parts[0].header["dataWindow"][1].tolist() == [31, 15]


def _clip(path: Path) -> None:
    from tests.warp.test_video_warp_imports import _clip as clip

    clip(path)


@pytest.mark.parametrize("total, char", [(200, "a"), (250, "é"), (255, "中")])
def test_a_clip_is_written_to_a_long_name(tmp_path, total, char):
    av = pytest.importorskip("av")
    src = tmp_path / "clip.mp4"
    _clip(src)
    out = tmp_path / _name(total, ".mp4", char)
    assert main(["warp", str(src), "-o", str(out), "--from", "equirect", "--to", "fisheye:fov=180",
                 "--size", "32x32", "-q"]) == 0
    assert sorted(os.listdir(tmp_path)) == sorted(["clip.mp4", out.name])
    with av.open(str(out)) as c:  # FFmpeg reads the clip written
        assert (c.streams.video[0].codec_context.width, c.streams.video[0].frames) == (32, 3)


@pytest.mark.parametrize("command", ["convert", "warp", "clip"])
@pytest.mark.parametrize("total, char", [(256, "a"), (257, "é"), (300, "🙂")])
def test_a_name_over_255_bytes_is_one_line(tmp_path, capsys, command, total, char):
    src = tmp_path / ("clip.mp4" if command == "clip" else "in.exr")
    _clip(src) if command == "clip" else _image(src)
    out = tmp_path / _name(total, ".mp4" if command == "clip" else ".png", char)
    with pytest.raises(OSError) as kernel:  # the kernel itself refuses the name
        os.close(os.open(out, os.O_WRONLY | os.O_CREAT, 0o600))
    assert kernel.value.errno == 36  # ENAMETOOLONG on Linux
    args = ["convert", str(src), "-o", str(out)] if command == "convert" else \
        ["warp", str(src), "-o", str(out), "--from", "equirect", "--to", "fisheye:fov=180", "--size", "32x32"]
    assert main(args) == 1
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and out.name[:24] in lines[0] and lines[0].endswith(
        f": its name is too long: {total} bytes, where a file name holds at most 255; give a shorter name"), lines
    assert sorted(os.listdir(tmp_path)) == [src.name]


_KILLED_WRITER = """
import sys
from pathlib import Path
from lenslab.atomic import atomic_write_path
with atomic_write_path(Path(sys.argv[1]), overwrite=False) as tmp:
    tmp.write_bytes(b"half a PNG")
    print(tmp.name, flush=True)
    sys.stdin.read()  # held open until killed
"""


def test_the_sweep_finds_a_killed_runs_temporary_of_a_250_byte_name(tmp_path):
    src_dir, out_dir = tmp_path / "in", tmp_path / "out"
    src_dir.mkdir()
    out_dir.mkdir()
    stem = _name(250, ".png", "é")[:-4]
    _image(src_dir / f"{stem}.exr")
    target = out_dir / f"{stem}.png"
    child = subprocess.Popen([sys.executable, "-c", _KILLED_WRITER, str(target)], stdin=subprocess.PIPE,
                             stdout=subprocess.PIPE, text=True)
    try:
        left = child.stdout.readline().strip()  # the state waited for: the temporary is on disk
        child.send_signal(signal.SIGKILL)
        child.wait(timeout=HANG_GUARD)
    finally:
        if child.poll() is None:
            child.kill()
    assert os.listdir(out_dir) == [left] and len(left.encode()) <= 255 and f"-{child.pid}-" in left
    from lenslab.atomic import temporaries

    assert [p.name for p in temporaries(target)] == [left]
    assert temporaries(out_dir / f"{stem[:-1]}b.png") == []  # another long name, alike for 248 bytes: not its
    run = subprocess.run([sys.executable, "-m", "lenslab", "convert", str(src_dir), "-o", str(out_dir),
                          "--to", "png", "--skip-existing", "-q"], capture_output=True, text=True, timeout=HANG_GUARD)
    assert run.returncode == 0, run.stderr
    assert os.listdir(out_dir) == [target.name]  # the temporary swept, the output written
