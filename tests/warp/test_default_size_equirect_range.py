"""A warp without ``--size`` into an equirect of part of the sphere keeps square pixels at the source's resolution:
a source of 512 rows over 180 degrees has 512 / 180 pixels a degree, so a band of latitudes -45 to 45 is 90 * 512 /
180 = 256 rows by 360 * 512 / 180 = 1024 columns, and longitudes -90 to 90 are 512 columns by 512 rows (the formula
transcribed here; the size read back by OpenEXR's own binding). Before, every equirect was 2:1 whatever its range,
stretching a band twice its height."""

from __future__ import annotations

import numpy as np
import OpenEXR
import pytest

from lenslab.cli.main import main
from lenslab.io import write

ROWS = 512  # the source's rows over 180 degrees


def _size(path) -> tuple[int, int]:
    with OpenEXR.File(str(path)) as f:
        (x0, y0), (x1, y1) = f.header()["dataWindow"]
    return int(x1 - x0 + 1), int(y1 - y0 + 1)


@pytest.mark.parametrize("to, lon, lat", [
    ("equirect:lat_min=-45,lat_max=45", 360, 90),
    ("equirect:lon_min=-90,lon_max=90", 180, 180),
    ("equirect:lon_min=0,lon_max=90,lat_min=0,lat_max=30", 90, 30),
    ("stereo:tb,base=equirect,lat_min=-45,lat_max=45", 360, 90),  # each eye
    ("equirect", 360, 180),
])
def test_an_equirect_range_keeps_square_pixels(tmp_path, to, lon, lat):
    src = tmp_path / "pano.exr"
    write(src, np.full((ROWS, 2 * ROWS, 3), 0.5, np.float32))
    out = tmp_path / "out.exr"
    assert main(["warp", str(src), "-o", str(out), "--to", to, "-q"]) == 0
    w, h = round(lon * ROWS / 180), round(lat * ROWS / 180)
    if to.startswith("stereo:tb"):
        h *= 2
    assert _size(out) == (w, h)
