"""A warp without ``--size`` keeps the source's angular resolution (pixels per degree), whatever the source's
layout: a cube map's faces hold 90 degrees each, so 256-pixel faces give the same equirect from a 6x1 strip as
from a 1x6 column (it used to come from the image's rows: 512x256 from the one, 3072x1536 from the other), and
a cube map warped to a cube map keeps its 256-pixel faces (it used to halve them). One eye of a stereo frame
holds the rows of 180 degrees, whether the eyes sit side by side or one above the other.

The expected sizes are computed here from the geometry alone: a cube face spans 90 degrees, an equirect 360 by
180 degrees, a 180-degree fisheye 180 degrees across.
"""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import read, write

FACE = 256  # pixels across a cube face
PER_DEGREE = FACE / 90.0  # a face spans 90 degrees (the cube's half-angle is 45 degrees)


@pytest.fixture(scope="module")
def cubes(tmp_path_factory):
    """Cube maps of 256-pixel faces in four layouts, each warped from one panorama (the file records its lens)."""
    folder = tmp_path_factory.mktemp("cubes")
    pano = folder / "pano.exr"
    rng = np.random.default_rng(11)
    write(pano, np.exp(rng.normal(0, 1, (256, 512, 3))).astype(np.float32))
    made = {}
    for layout, (cols, rows) in {"6x1": (6, 1), "1x6": (1, 6), "3x2": (3, 2), "4x3": (4, 3)}.items():
        made[layout] = folder / f"cube-{layout}.exr"
        assert main(["warp", str(pano), "-o", str(made[layout]), "--to", f"cubemap:layout={layout}",
                     "--size", f"{cols * FACE}x{rows * FACE}", "-q"]) == 0
    return made


def _size(path) -> tuple[int, int]:
    return tuple(read(path)[1]["size"])


@pytest.mark.parametrize("layout", ["6x1", "1x6", "3x2", "4x3"])
def test_a_cube_map_gives_the_equirect_of_its_faces_resolution(tmp_path, cubes, layout):
    out = tmp_path / "pano.exr"
    assert main(["warp", str(cubes[layout]), "-o", str(out), "--to", "equirect", "-q"]) == 0
    assert _size(out) == (round(360 * PER_DEGREE), round(180 * PER_DEGREE))  # 1024 x 512


@pytest.mark.parametrize("layout", ["6x1", "1x6", "3x2", "4x3"])
def test_cube_to_cube_keeps_the_faces(tmp_path, cubes, layout):
    out = tmp_path / "strip.exr"
    assert main(["warp", str(cubes[layout]), "-o", str(out), "--to", "cubemap:layout=6x1", "-q"]) == 0
    face = round(90 * PER_DEGREE)
    assert _size(out) == (6 * face, face)


def test_a_fisheye_from_a_cube_map_spans_180_degrees_at_its_resolution(tmp_path, cubes):
    out = tmp_path / "fish.exr"
    assert main(["warp", str(cubes["1x6"]), "-o", str(out), "--to", "fisheye:fov=180", "-q"]) == 0
    side = round(180 * PER_DEGREE)
    assert _size(out) == (side, side)


@pytest.mark.parametrize("layout", ["sbs", "tb"])
def test_a_stereo_source_gives_one_eye_s_resolution(tmp_path, layout):
    """Eyes of 128x64 equirect (64 rows of 180 degrees): the mono equirect made of them is 128x64 either way."""
    src = tmp_path / "eyes.exr"
    size = (256, 64) if layout == "sbs" else (128, 128)
    write(src, np.full((size[1], size[0], 3), 0.5, np.float32))
    out = tmp_path / "mono.exr"
    assert main(["warp", str(src), "-o", str(out), "--from", f"stereo:{layout},base=equirect", "--to", "equirect",
                 "-q"]) == 0
    per_degree = 64 / 180.0
    assert _size(out) == (round(360 * per_degree), round(180 * per_degree))
