"""A video warp's start-up: what ``lenslab warp clip.mp4 -o fish.mp4`` loads before its first frame, what
``lenslab warp --help`` loads, and the warm install ``lenslab bench video`` measures.

Each is read from a fresh interpreter: ``sys.modules`` after the command (the interpreter's own record), or the
bytecode files the interpreter wrote. The clip is made by PyAV; the benchmark's clip by ffmpeg."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("av")

from tests.warp.test_video_warp_imports import _clip  # noqa: E402  (a 3-frame H.264 clip, by PyAV)

#: the command modules a warp may load: the entry point, its own and the display options it shares
WARP_COMMANDS = {"lenslab.cli", "lenslab.cli.main", "lenslab.cli.warp", "lenslab.cli.display"}
#: readers of other formats, calibration files and the lens database; a clip's warp reads none of them
READERS = ("lenslab.io.exr", "lenslab.io.tiff", "lenslab.io.ldr", "lenslab.io.pfm", "lenslab.io.pnm",
           "lenslab.io.rgbe", "lenslab.io.ocio", "lenslab.io.colour.png_cicp", "lenslab.calibfiles.",
           "lenslab.lenses.lensfun.database", "lenslab.stmap", "lenslab.metrics")
#: the libraries behind those readers, and the progress bar a quiet run does not show
LIBRARIES = ("OpenEXR", "Imath", "tifffile", "PIL", "imageio", "PyOpenColorIO", "OpenImageIO", "tqdm",
             "matplotlib", "lensfunpy")


def _loaded_after(argv: list[str]) -> tuple[int, list[str], str]:
    """The exit status, every module in sys.modules afterwards and what was printed, of `lenslab ARGV` in a fresh
    interpreter."""
    code = ("import contextlib, io, json, sys\n"
            "from lenslab.cli.main import main\n"
            "out = io.StringIO()\n"
            "with contextlib.redirect_stdout(out):\n"
            "    try:\n"
            f"        status = main({argv!r})\n"
            "    except SystemExit as exc:\n"
            "        status = exc.code\n"
            "print(json.dumps([status, sorted(sys.modules), out.getvalue()]))")
    done = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True)
    status, loaded, printed = json.loads(done.stdout.strip().splitlines()[-1])
    return status, loaded, printed


def test_a_video_warp_loads_no_other_command_reader_or_progress_bar(tmp_path):
    clip = tmp_path / "clip.mp4"
    _clip(clip)
    status, loaded, _ = _loaded_after(["warp", str(clip), "-o", str(tmp_path / "fish.mp4"), "--to", "fisheye:fov=180",
                                       "--from", "equirect", "--size", "64x64", "-q"])
    assert status == 0 and (tmp_path / "fish.mp4").stat().st_size > 0
    assert "av" in loaded and "lenslab.io.video.clips" in loaded  # the warp did decode and encode here
    assert sorted(m for m in loaded if m.startswith("lenslab.cli")) == sorted(WARP_COMMANDS)
    assert [m for m in loaded if m.startswith(READERS) or m in READERS] == []
    assert [m for m in loaded if m.split(".")[0] in LIBRARIES] == []


def test_warp_help_names_the_video_options_and_loads_neither_numpy_nor_pyav():
    status, loaded, printed = _loaded_after(["warp", "--help"])
    assert status == 0
    assert "--frames A:B" in printed and "--codec" in printed and "fish.mp4" in printed
    assert [m for m in loaded if m.split(".")[0] in ("numpy", "av")] == []


@pytest.mark.skipif(shutil.which("ffmpeg") is None, reason="the video benchmark's baseline is ffmpeg")
def test_the_video_benchmark_times_a_warm_install_where_the_shell_forbids_bytecode(tmp_path):
    """A shell with PYTHONDONTWRITEBYTECODE would make every timed run compile lenslab's modules from source,
    which an installed lenslab never does: the benchmark's uncounted first run writes Python's bytecode cache (here
    under PYTHONPYCACHEPREFIX, where the interpreter puts it) for the timed runs to read."""
    cache = tmp_path / "pycache"
    env = {**os.environ, "PYTHONDONTWRITEBYTECODE": "1", "PYTHONPYCACHEPREFIX": str(cache)}
    done = subprocess.run([sys.executable, "-m", "lenslab", "bench", "video", "--frames", "2", "--repeat", "1",
                           "--sizes", "64x32", "--json", str(tmp_path / "video.json")],
                          env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    warp = Path(__file__).resolve().parents[2] / "lenslab" / "cli" / "warp.py"
    tag = sys.implementation.cache_tag
    written = cache / warp.parent.relative_to(warp.anchor) / f"warp.{tag}.pyc"
    assert written.is_file(), sorted(p.name for p in cache.rglob("*.pyc"))[:20]
    figures = {f["key"] for f in json.loads((tmp_path / "video.json").read_text())["figures"]}
    assert {"video.64x32_wall", "video.64x32_cpu"} <= figures
