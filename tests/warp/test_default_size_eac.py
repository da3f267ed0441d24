"""A warp without ``--size`` into an equi-angular cube map makes square faces of whole pixels at the source's
resolution, as a cube map's are: faces of 90 of the source's 180 degrees (R * 90 / 180 rows from R rows), three
across and two down, with ``pad`` pixels round each row of faces (the model's layout: a face is (W - 2 pad) / 3
wide and H / 2 - 2 pad tall). Worked out here from those angles; sizes read back by OpenEXR's own binding. Before,
the frame was 3:2 of R rows whatever the padding, so an odd R (485) gave faces of 242.67 x 242.5 pixels."""

from __future__ import annotations

import numpy as np
import OpenEXR
import pytest

from lenslab.cli.main import main
from lenslab.io import write


def _size(path) -> tuple[int, int]:
    with OpenEXR.File(str(path)) as f:
        (x0, y0), (x1, y1) = f.header()["dataWindow"]
    return int(x1 - x0 + 1), int(y1 - y0 + 1)


@pytest.mark.parametrize("rows", [512, 485])
@pytest.mark.parametrize("pad", [0, 2])
def test_square_faces_of_whole_pixels(tmp_path, rows, pad):
    src = tmp_path / "pano.exr"
    write(src, np.full((rows, 2 * rows, 3), 0.5, np.float32))
    out = tmp_path / "eac.exr"
    assert main(["warp", str(src), "-o", str(out), "--to", f"eac:pad={pad}", "-q"]) == 0
    face = rows * 90 // 180
    assert _size(out) == (3 * face + 2 * pad, 2 * face + 4 * pad)
