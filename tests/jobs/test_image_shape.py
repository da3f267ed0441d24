"""One image-shape check with one error type, whichever stage meets the bad array first."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.errors import FitError, FormatError, ImageShapeError, WarpError

BAD = {"empty rows": np.zeros((0, 5, 3), np.float32), "a vector": np.zeros(7, np.float32),
       "four axes": np.zeros((2, 2, 2, 2), np.float32), "strings": np.full((2, 2, 3), "x"),
       "no channel": np.zeros((3, 3, 0), np.float32)}


def _stages(tmp_path):
    from lenslab.io import write
    from lenslab.lenses import Camera
    from lenslab.metrics.measures import rmse
    from lenslab.warp import warp
    from lenslab.warp.given import warp_with_map

    src = Camera.from_spec("equirect", (8, 4))
    dst = Camera.from_spec("perspective:fov=60", (4, 4))
    xy = np.zeros((4, 4, 2), np.float64)
    return {"write": lambda a: write(tmp_path / "x.exr", a),
            "warp": lambda a: warp(a, src, dst),
            "warp by a map": lambda a: warp_with_map(a, xy),
            "measure": lambda a: rmse(a, a)}


@pytest.mark.parametrize("case", sorted(BAD))
@pytest.mark.parametrize("stage", ["write", "warp", "warp by a map", "measure"])
def test_every_stage_refuses_a_non_image_with_the_one_error_type(tmp_path, stage, case):
    with pytest.raises(ImageShapeError, match="H x W|numbers|channels"):
        _stages(tmp_path)[stage](BAD[case])


def test_the_one_type_is_each_stage_s_own_type_too():
    # callers that catch the stage's own error (FormatError from io, WarpError from warp) keep working
    assert issubclass(ImageShapeError, FormatError) and issubclass(ImageShapeError, WarpError)
    assert issubclass(ImageShapeError, FitError) and issubclass(ImageShapeError, ValueError)
