"""``tracer render --camera flop.exr`` renders through the camera a ``lenslab warp --flip`` output records, mirror
included: the render records (and so traced) each pixel's ray as the mirrored view's, the perspective formula of
``docs/conventions.md`` mirrored and turned, written out in float64 (``tests/warp/test_flip_records_mirror.py``)."""

from __future__ import annotations

import numpy as np

from lenslab.io import read
from tests.warp.test_flip_records_mirror import FOV, H, W, _flop_of_yaw_30, _recorded_rays, _source, _warp
from tracer.cli import main


def test_a_render_through_a_flops_camera_keeps_its_mirror(tmp_path):
    _warp(_source(tmp_path / "src.exr"), tmp_path / "flop.exr", "--to", f"perspective:fov={FOV:g}", "--yaw", "30",
          "--flip", "h")
    assert main(["render", "--scene", "furnace", "--camera", str(tmp_path / "flop.exr"), "--spp", "1", "-q", "-o",
                 str(tmp_path / "render.exr")]) == 0
    image, meta = read(tmp_path / "render.exr")
    assert image.shape[:2] == (H, W)
    np.testing.assert_allclose(_recorded_rays(meta), _flop_of_yaw_30(), rtol=0, atol=1e-12)
