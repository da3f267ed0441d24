"""``tracer render --camera IMAGE`` says where it puts the eye: the one the image records (a render's), or the scene's
own where the image records its camera at the origin, which places nothing (a panorama lenslab warped from a
photograph). The help said "eye (unless --eye)" only, and a warp's view was rendered from the scene's eye unsaid.

Outside values: the eye ``tracer render`` of the scene with no --camera records (the scene's own view), and the eye
given to the render that made the image; each read back from the EXR header (the
``lenslab.camera`` attribute)."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main as lenslab
from lenslab.io import read, write
from tracer.cli import main as tracer


def _eye(path):
    return tuple(np.round(np.asarray(read(path)[1]["camera"].pose.eye, np.float64), 6))


def test_the_help_and_the_eye(tmp_path, capsys):
    with pytest.raises(SystemExit):
        tracer(["render", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "eye (unless --eye; the scene's own for an image that records its camera at the origin, as a lenslab " \
           "warp of a photograph does)" in text
    common = ["--scene", "cornell", "--spp", "1", "-q", "--size", "16x12"]
    assert tracer(["render", *common, "-o", str(tmp_path / "own.exr")]) == 0
    y, x = np.mgrid[0:16, 0:32]
    pano = tmp_path / "pano.exr"
    write(pano, np.stack([(x + 0.5) / 32, (y + 0.5) / 16, 0.25 + 0 * x], -1).astype(np.float32), pixel_type="float")
    assert lenslab(["warp", str(pano), "-o", str(tmp_path / "view.exr"), "--to", "perspective:fov=60", "--size",
                    "16x12", "--yaw", "20", "-q"]) == 0
    assert _eye(tmp_path / "view.exr") == (0.0, 0.0, 0.0)
    assert tracer(["render", *common, "--camera", str(tmp_path / "view.exr"), "-o", str(tmp_path / "a.exr")]) == 0
    assert _eye(tmp_path / "a.exr") == _eye(tmp_path / "own.exr")
    assert tracer(["render", *common, "--camera", "perspective:fov=60", "--eye", "0.1,0.2,-0.3",
                   "-o", str(tmp_path / "placed.exr")]) == 0
    assert tracer(["render", *common, "--camera", str(tmp_path / "placed.exr"), "-o", str(tmp_path / "b.exr")]) == 0
    assert _eye(tmp_path / "b.exr") == (0.1, 0.2, -0.3)
