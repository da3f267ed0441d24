"""``tracer render --camera render.exr`` renders the view that EXR records, as ``lenslab warp --to render.exr``
takes it: the lens, the orientation, the eye and the size written into its header (it used to take the lens
only, posed at the scene's own view). A render at yaw 30, pitch -15, roll 5 from an eye inside the box, made
again from its own file at the same seed, is the same image bit for bit (the tracer is deterministic at a seed:
its samples come from the seed and the pixel alone). As with ``lenslab warp --to render.exr``, ``--eye`` moves
that view and options that would turn it are refused (exit 2), naming the lens spec to give instead.
"""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.io import read
from tracer.cli import main

YPR = (30.0, -15.0, 5.0)  # degrees, as given on the command line
EYE = (0.2, 0.3, 0.1)  # inside the Cornell box, off the scene's own view
ARGS = ["render", "--scene", "cornell-point", "--spp", "2", "--seed", "7", "--integrator", "direct", "-q"]


@pytest.fixture(scope="module")
def first(tmp_path_factory):
    out = tmp_path_factory.mktemp("view") / "first.exr"
    assert main([*ARGS, "--camera", "fisheye:fov=150", "--size", "40x30", "--yaw", str(YPR[0]), "--pitch",
                 str(YPR[1]), "--roll", str(YPR[2]), "--eye", ",".join(map(str, EYE)), "-o", str(out)]) == 0
    return out


def test_the_header_records_the_pose_given(first):
    camera = read(first)[1]["camera"]
    np.testing.assert_allclose(camera.pose.ypr, YPR, atol=1e-9)  # angles back through a rotation matrix
    np.testing.assert_allclose(camera.pose.eye, EYE, atol=0)
    assert camera.size == (40, 30)


def test_rendering_the_file_again_gives_the_same_image(first, tmp_path):
    again = tmp_path / "again.exr"
    assert main([*ARGS, "--camera", str(first), "-o", str(again)]) == 0
    image, meta = read(again)
    original, recorded = read(first)
    assert image.shape == original.shape == (30, 40, original.shape[2])
    np.testing.assert_array_equal(image, original)  # same rays, same seed: the same floats
    np.testing.assert_allclose(meta["camera"].pose.ypr, YPR, atol=1e-9)
    np.testing.assert_allclose(meta["camera"].pose.eye, EYE, atol=0)


def test_size_still_resizes_the_recorded_view(first, tmp_path):
    out = tmp_path / "big.exr"
    assert main([*ARGS, "--camera", str(first), "--size", "80x60", "-o", str(out)]) == 0
    camera = read(out)[1]["camera"]
    assert camera.size == (80, 60)
    np.testing.assert_allclose(camera.pose.ypr, YPR, atol=1e-9)


def test_eye_moves_the_recorded_view(first, tmp_path):
    out = tmp_path / "moved.exr"
    assert main([*ARGS, "--camera", str(first), "--eye", "0.1,0.2,0.3", "-o", str(out)]) == 0
    camera = read(out)[1]["camera"]
    np.testing.assert_allclose(camera.pose.ypr, YPR, atol=1e-9)
    np.testing.assert_allclose(camera.pose.eye, (0.1, 0.2, 0.3), atol=0)
    assert not np.array_equal(read(out)[0], read(first)[0])  # another place in the box sees another image


@pytest.mark.parametrize("option", [["--yaw", "10"], ["--pitch", "0"], ["--roll", "1"], ["--look-at", "0,0,1"],
                                    ["--up", "0,1,0"], ["--view", "default"]])
def test_pose_options_with_a_recorded_view_are_refused(first, tmp_path, capsys, option):
    out = tmp_path / "r.exr"
    assert main([*ARGS, "--camera", str(first), *option, "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and option[0] in err[0], err
    assert "yaw 30, pitch -15, roll 5" in err[0] and "--camera fisheye:" in err[0], err
    assert not out.exists()


def test_a_view_recorded_at_the_origin_is_seen_from_the_scene_s_eye(tmp_path):
    """lenslab records a view made of a photographed panorama at the origin, which places nothing (as ``lenslab warp
    --to`` reads it): the tracer takes that view's lens and orientation from the scene view's eye, the Cornell box's
    camera position (0.278, 0.273, 0.001) published with the scene."""
    from lenslab.cli.main import main as lenslab_main
    from lenslab.io import write

    pano = tmp_path / "photo.exr"
    write(pano, np.full((32, 64, 3), 0.5, np.float32))
    view = tmp_path / "view.exr"
    assert lenslab_main(["warp", str(pano), "-o", str(view), "--to", "perspective:fov=70", "--size", "24x16",
                         "--yaw", "30", "--pitch", "-15", "--roll", "5", "-q"]) == 0
    assert not np.any(read(view)[1]["camera"].pose.eye)
    out = tmp_path / "traced.exr"
    assert main([*ARGS, "--camera", str(view), "-o", str(out)]) == 0
    camera = read(out)[1]["camera"]
    np.testing.assert_allclose(camera.pose.ypr, YPR, atol=1e-9)
    np.testing.assert_allclose(camera.pose.eye, (0.278, 0.273, 0.001), atol=1e-12)
    assert camera.size == (24, 16)
