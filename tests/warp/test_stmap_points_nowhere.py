"""``lenslab warp --stmap``: a map none of whose pixels points into the source (alpha 0 everywhere, or no finite
s, t within [0, 1]) would make a wholly transparent image; it is refused as a failed input (exit 1, one line)
and nothing is written. The maps are written by OpenImageIO, as another tool would."""

from __future__ import annotations

import numpy as np
import pytest

import lenslab.io as lio
from lenslab.cli.main import main

oiio = pytest.importorskip("OpenImageIO")


def oiio_exr(path, pixels):
    h, w, c = pixels.shape
    out = oiio.ImageOutput.create(str(path))
    out.open(str(path), oiio.ImageSpec(w, h, c, oiio.FLOAT))
    out.write_image(np.ascontiguousarray(pixels, np.float32))
    out.close()
    return path


@pytest.mark.parametrize("pixels", [
    np.dstack([np.full((4, 6), 0.5), np.full((4, 6), 0.5), np.zeros((4, 6)), np.zeros((4, 6))]),  # alpha 0
    np.dstack([np.full((4, 6), 3.0), np.full((4, 6), np.nan), np.zeros((4, 6))]),  # s beyond 1, t NaN
])
def test_a_map_that_points_nowhere_is_refused(tmp_path, capsys, pixels):
    src = lio.write(tmp_path / "src.exr", np.ones((8, 16, 3), np.float32))
    st = oiio_exr(tmp_path / "map.exr", pixels)
    out = tmp_path / "out.exr"
    assert main(["warp", str(src), "--stmap", str(st), "-o", str(out)]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "no pixel of this image points into the source" in err[0], err
    assert not out.exists()


def test_one_pixel_that_points_in_is_enough(tmp_path):
    src = lio.write(tmp_path / "src.exr", np.ones((8, 16, 3), np.float32))
    pixels = np.dstack([np.full((4, 6), 3.0), np.full((4, 6), 3.0), np.zeros((4, 6))])
    pixels[1, 2, :2] = 0.5
    st = oiio_exr(tmp_path / "map.exr", pixels)
    assert main(["warp", str(src), "--stmap", str(st), "-o", str(tmp_path / "out.exr")]) == 0
