"""A plain warp starts without the JIT: ``lenslab warp`` of an EXR into a fisheye (any reconstruction filter,
a cube map source too) runs on the compiled extension alone, so numba, llvmlite and scipy (which numba
imports) never load, nor OpenCV. Checked in a fresh interpreter, by what ``sys.modules`` holds afterwards."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

from lenslab import io

NOT_LOADED = ("numba", "llvmlite", "scipy", "cv2")


def _loaded_after_warp(argv: list[str]) -> tuple[int, list[str]]:
    code = ("import json, sys\n"
            "from lenslab.cli.main import main\n"
            f"status = main({argv!r})\n"
            f"print(json.dumps([status, sorted(m for m in {NOT_LOADED!r} if m in sys.modules)]))")
    out = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True).stdout
    status, loaded = json.loads(out.strip().splitlines()[-1])
    return status, loaded


@pytest.mark.parametrize("filter_name", ["bilinear", "bicubic", "lanczos", "nearest"])
def test_a_plain_warp_loads_no_jit(tmp_path, filter_name):
    src = tmp_path / "pano.exr"
    io.write(str(src), np.random.default_rng(0).uniform(0, 4, (128, 256, 3)).astype(np.float32))
    status, loaded = _loaded_after_warp(["warp", str(src), "-o", str(tmp_path / "out.exr"), "--to", "fisheye:fov=180",
                                         "--size", "128x128", "--filter", filter_name])
    assert status == 0
    assert loaded == []
    assert (tmp_path / "out.exr").is_file()


def test_a_cube_map_source_loads_no_jit(tmp_path):
    src = tmp_path / "cube.exr"
    io.write(str(src), np.random.default_rng(1).uniform(0, 4, (128, 192, 3)).astype(np.float32))
    status, loaded = _loaded_after_warp(["warp", str(src), "-o", str(tmp_path / "out.exr"), "--from", "cubemap",
                                         "--to", "fisheye:fov=200", "--size", "96x96", "--filter", "bicubic"])
    assert status == 0
    assert loaded == []
