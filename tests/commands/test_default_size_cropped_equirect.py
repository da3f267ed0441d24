"""A warp without ``--size`` keeps the source's pixels per degree for an equirect that covers part of the
sphere too: a 1024 x 256 band of latitudes -45 to 45 degrees holds 256 rows over 90 degrees (2.84 pixels a
degree, as its 1024 columns over 360 degrees do), so its full equirect is 1024 x 512 and a 180-degree
fisheye of it 512 x 512; the rows over 180 degrees (a 512 x 256 equirect, half its resolution) were taken.
The expected sizes come from the band's geometry alone."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import read, write

ROWS, LAT = 256, 90.0  # the band's rows and the degrees of latitude they span


@pytest.mark.parametrize("to, expected", [("equirect", (round(360 * ROWS / LAT), round(180 * ROWS / LAT))),
                                          ("fisheye:fov=180", (round(180 * ROWS / LAT),) * 2)])
def test_a_band_of_latitudes_keeps_its_resolution(tmp_path, to, expected):
    src = tmp_path / "band.exr"
    write(src, np.full((ROWS, 1024, 3), 0.5, np.float32))
    out = tmp_path / "out.exr"
    assert main(["warp", str(src), "-o", str(out), "--from", "equirect:lat_min=-45,lat_max=45", "--to", to,
                 "-q"]) == 0
    assert tuple(read(out)[1]["size"]) == expected
