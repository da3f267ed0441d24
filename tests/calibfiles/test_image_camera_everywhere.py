"""An image that records its camera (an EXR written by tracer or lenslab) is a camera wherever lenslab takes
a camera file, as ``lenslab camera show`` takes it and ``lenslab camera --help`` promises ("the same files
work wherever lenslab takes a lens: warp --from/--to, fit, tracer"): ``warp --to``, ``fit lens --from``,
``tracer render --camera``, at the size asked. An image without a camera is one line naming what to give."""

from __future__ import annotations

import numpy as np
import pytest

import lenslab
from lenslab.cli.main import main
from tracer.cli import main as tracer

SPEC = "fisheye:fov=150,mapping=equisolid"


@pytest.fixture
def render(tmp_path, capsys):
    exr = tmp_path / "r.exr"
    assert tracer(["render", "--scene", "furnace", "--camera", SPEC, "--size", "48x32", "--spp", "1", "-q",
                   "-o", str(exr)]) == 0
    capsys.readouterr()
    return exr


def _equisolid_radius(theta_deg, half_fov_deg=75.0):
    """Equisolid fisheye in float64: r = sin(theta / 2) / sin(F / 2), 1 at the edge of its 150 degrees."""
    return np.sin(np.radians(theta_deg) / 2) / np.sin(np.radians(half_fov_deg) / 2)


def test_make_lens_takes_the_render_at_its_size_and_another(render):
    from lenslab.lenses import make_lens

    lens = make_lens(str(render))
    assert (lens.width, lens.height) == (48, 32) and lens.spec() == make_lens(SPEC, (48, 32)).spec()
    big = make_lens(str(render), (96, 64))
    assert (big.width, big.height) == (96, 64)
    # the ray 60 degrees off the axis to the right lands at the equisolid radius of the 96-wide image
    d = np.array([[np.sin(np.radians(60)), 0.0, np.cos(np.radians(60))]])
    xy, ok = big.dir_to_pixel(d)
    assert ok[0] and abs(xy[0, 0] - (48 + 48 * _equisolid_radius(60))) < 1e-9


def test_warp_to_the_camera_of_a_render(render, tmp_path, capsys):
    src = tmp_path / "pano.exr"
    lenslab.write(src, np.ones((32, 64, 3), np.float32))
    out = tmp_path / "view.exr"
    assert main(["warp", str(src), "--to", str(render), "-o", str(out), "-q"]) == 0
    img, meta = lenslab.read(out)
    assert tuple(meta["size"]) == (48, 32) and meta["camera"].lens.spec() == lenslab.read(render)[1]["camera"].lens.spec()


def test_fit_lens_from_a_render(render, capsys):
    assert main(["fit", "lens", "--from", str(render), "--model", "fisheye:mapping=equisolid"]) == 0
    assert "fitted:   fisheye:fov=150" in capsys.readouterr().out


def test_tracer_renders_through_the_camera_of_a_render(render, tmp_path):
    out = tmp_path / "again.exr"
    assert tracer(["render", "--scene", "furnace", "--camera", str(render), "--spp", "1", "-q", "-o", str(out)]) == 0
    assert tuple(lenslab.read(out)[1]["size"]) == (48, 32)


def test_an_image_without_a_camera_says_so(tmp_path, capsys):
    png = tmp_path / "plain.png"
    lenslab.write(png, np.ones((4, 8, 3), np.float32) * 0.5)
    src = tmp_path / "pano.exr"
    lenslab.write(src, np.ones((32, 64, 3), np.float32))
    assert main(["warp", str(src), "--to", str(png), "-o", str(tmp_path / "v.exr")]) == 2  # not a lens: usage
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "records no camera" in err[0] and "UTF-8" not in err[0], err


@pytest.mark.parametrize("make", ["yaml", "spec"])
def test_tracer_renders_a_calibrated_camera_at_its_own_size(tmp_path, make):
    # OpenCV's camera of a 64 x 48 image: rendered at 64 x 48 with fx = fy = 50 as calibrated, not squeezed
    # into 512 x 512 (fx 400, fy 533: another camera)
    spec = "opencv:fx=50,fy=50,cx=31.5,cy=23.5,k1=-0.1,width=64,height=48"
    if make == "yaml":
        cam = tmp_path / "calib.yaml"
        assert main(["camera", "convert", spec, "-o", str(cam)]) == 0
        spec = str(cam)
    out = tmp_path / "r.exr"
    assert tracer(["render", "--scene", "furnace", "--camera", spec, "--spp", "1", "-q", "-o", str(out)]) == 0
    lens = lenslab.read(out)[1]["camera"].lens
    assert (lens.width, lens.height) == (64, 48) and (lens.fx, lens.fy) == (50.0, 50.0)
