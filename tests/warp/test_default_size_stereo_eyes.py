"""A warp without ``--size`` into a stereo frame holds two views of the sphere, so its limit is twice the source's
pixels for each eye: a 3x2 cube map of 256-pixel faces (768 x 512) into a side-by-side equirect pair keeps the
source's 2.84 pixels a degree (two 1024 x 512 eyes, 2048 x 512, no note), where the limit of twice the source's
pixels for the whole frame cut it to 1772 x 443; a narrow photo is still limited, to twice its pixels an eye
(a 4:1 frame of h rows with 4 h^2 = 2 * 2 * 400 * 300). Sizes worked out here, read back by OpenEXR's binding."""

from __future__ import annotations

import math

import numpy as np
import OpenEXR

from lenslab.cli.main import main
from lenslab.io import write


def _size(path) -> tuple[int, int]:
    with OpenEXR.File(str(path)) as f:
        (x0, y0), (x1, y1) = f.header()["dataWindow"]
    return int(x1 - x0 + 1), int(y1 - y0 + 1)


def _warp(tmp_path, capsys, shape, source, to):
    src = tmp_path / "src.exr"
    write(src, np.full((*shape, 3), 0.5, np.float32))
    out = tmp_path / "out.exr"
    capsys.readouterr()
    assert main(["warp", str(src), "-o", str(out), "--from", source, "--to", to]) == 0
    return _size(out), [line for line in capsys.readouterr().err.splitlines() if "without --size" in line]


def test_a_cube_map_into_a_stereo_pair_keeps_its_resolution(tmp_path, capsys):
    size, notes = _warp(tmp_path, capsys, (512, 768), "cubemap", "stereo")
    assert size == (2 * 1024, 512) and notes == []


def test_a_photo_into_a_stereo_pair_is_limited_per_eye(tmp_path, capsys):
    size, notes = _warp(tmp_path, capsys, (300, 400), "perspective:fov=70", "stereo")
    h = math.floor(math.sqrt(2 * 2 * 400 * 300 / 4))
    assert abs(size[1] - h) <= 1 and size[0] == 4 * size[1], size
    assert len(notes) == 1 and "per eye" in notes[0], notes
