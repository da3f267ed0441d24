"""``lenslab camera show/convert`` take an image that records its camera (EXR from tracer or lenslab) as the
calibration files do; an image without one cannot be a camera: a usage mistake (exit 2, one line). A model a
calibration format has no place for is refused in one line naming the user's output file (never a temporary
name), exit 2, with nothing written."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main

oiio = pytest.importorskip("OpenImageIO")


def test_show_reads_the_camera_a_render_records(tmp_path, capsys):
    from tracer.cli import main as tracer

    exr = tmp_path / "r.exr"
    assert tracer(["render", "--scene", "furnace", "--camera", "fisheye:fov=150,mapping=equisolid", "--size", "48x32",
                   "--spp", "1", "-q", "-o", str(exr)]) == 0
    capsys.readouterr()
    assert main(["camera", "show", str(exr)]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith(f"{exr}: fisheye ") and out[0].endswith(", 48x32")  # the size the render was given
    assert "  fov      150" in out and "  mapping  equisolid" in out


def test_an_image_without_a_camera_is_a_usage_mistake(tmp_path, capsys):
    exr = tmp_path / "plain.exr"  # written by OpenImageIO: no lenslab camera in its header
    out = oiio.ImageOutput.create(str(exr))
    out.open(str(exr), oiio.ImageSpec(8, 4, 3, oiio.HALF))
    out.write_image(np.ones((4, 8, 3), np.float32))
    out.close()
    assert main(["camera", "show", str(exr)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "records no camera" in err[0], err


@pytest.mark.parametrize("name, extra, words", [("cam.yaml", [], "OpenCV has no fisheye model"),
                                                ("cam.yaml", ["--format", "kalibr"], "Kalibr has no fisheye model"),
                                                ("cam.txt", [], "COLMAP has no fisheye model")])
def test_a_model_the_format_cannot_hold_names_the_output(tmp_path, capsys, name, extra, words):
    out = tmp_path / name
    assert main(["camera", "convert", "fisheye:fov=180", "--size", "64x64", "-o", str(out), *extra]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"lenslab camera convert: error: {out}: {words}"), err
    assert ".tmp" not in err[0] and list(tmp_path.iterdir()) == []
