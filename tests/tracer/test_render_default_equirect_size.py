"""``tracer render --camera equirect`` without ``--size`` renders square pixels: 512 rows over 180 degrees make a
whole equirect 1024 x 512 (not 512 x 512, pixels twice as tall as wide) and a band of latitudes -45 to 45 1024 x 256,
as ``lenslab warp`` makes them. The sizes are worked out from the angles; read back by OpenEXR's own binding."""

from __future__ import annotations

import OpenEXR
import pytest

from tracer.cli import main


@pytest.mark.parametrize("spec, lon, lat", [("equirect", 360, 180), ("equirect:lat_min=-45,lat_max=45", 360, 90)])
def test_square_pixels(tmp_path, spec, lon, lat):
    out = tmp_path / "pano.exr"
    assert main(["render", "--scene", "furnace", "--camera", spec, "--spp", "1", "-q", "-o", str(out)]) == 0
    with OpenEXR.File(str(out)) as f:
        (x0, y0), (x1, y1) = f.header()["dataWindow"]
    assert (int(x1 - x0 + 1), int(y1 - y0 + 1)) == (512 * lon // 180, 512 * lat // 180)
