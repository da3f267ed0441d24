"""A stereo (multi-view) EXR warped without a view name: the default view is warped, and the other view's colour
(``left.R``...) is said as another view's, with the name that warps it, not as depth or vectors of the source
camera. The file is written with OpenEXR's own binding; the view warped by its name is checked against the
values OpenEXR wrote."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main

OpenEXR = pytest.importorskip("OpenEXR")

H, W = 8, 16


def _stereo(path) -> None:
    channels = {"R": np.full((H, W), 0.125, np.float16), "G": np.full((H, W), 0.25, np.float16),
                "B": np.full((H, W), 0.375, np.float16), "left.R": np.full((H, W), 0.5, np.float16),
                "left.G": np.full((H, W), 0.625, np.float16), "left.B": np.full((H, W), 0.75, np.float16),
                "Z": np.full((H, W), 5.0, np.float32)}
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage, "multiView": ["right", "left"]}
    with OpenEXR.File(header, channels) as f:
        f.write(str(path))


def test_the_other_views_colour_is_named_as_a_view(tmp_path, capsys):
    src = tmp_path / "stereo.exr"
    _stereo(src)
    args = ["--to", "equirect", "--filter", "nearest"]
    assert main(["warp", str(src), "-o", str(tmp_path / "right.exr"), *args]) == 0
    notes = [line for line in capsys.readouterr().err.splitlines() if "not written" in line]
    assert notes == [
        f"lenslab warp: note: {src}: channel(s) 'left.B', 'left.G', 'left.R' not written: they belong to the other "
        "view(s) left (the file's default view, right, is warped); warp a view by its name, e.g. stereo.exr:left",
        f"lenslab warp: note: {src}: channel(s) 'Z' not written: a warp resamples colour and alpha only (depth, normals "
        "and vectors belong to the source camera)"]
    assert main(["warp", f"{src}:left", "-o", str(tmp_path / "left.exr"), *args]) == 0
    rgba = OpenEXR.File(str(tmp_path / "left.exr")).channels()["RGBA"].pixels  # (OpenEXR groups R, G, B, A)
    np.testing.assert_array_equal(rgba[..., :3], np.broadcast_to([0.5, 0.625, 0.75], (H, W, 3)))  # nearest, same grid
