"""``lenslab warp PANO --to render.exr`` from a panorama that records no place in the render's world: a
photographed panorama, or one lenslab made of it (``lenslab warp photo.exr --to cubemap`` records its camera
at the origin, as it records every output's). Such a panorama is the light arriving at the render's eye: the
view is made (it used to be refused for parallax when lenslab had written the panorama, since the origin is
not the render's eye) and the output records the render's eye and orientation, as the render does, so it can
be warped to the render again.

The expected eye and orientation are those ``tracer render`` wrote into its file; the expected centre
direction is the forward axis of the pose given to it (the rotation of docs/conventions.md, transcribed in
float64 in :mod:`tests.commands.test_warp_to_render_pose`)."""

from __future__ import annotations

import numpy as np

from lenslab.cli.main import main
from lenslab.io import read
from tests.commands.test_warp_to_render_pose import (PITCH, ROLL, YAW, _centre_direction, _direction_pano,
                                                     _rotation, render)  # noqa: F401 (the render fixture)


def _assert_the_render_s_view(out, render):
    np.testing.assert_allclose(_centre_direction(out), _rotation(YAW, PITCH, ROLL)[:, 2], atol=0.01)  # (as there)
    written, rendered = read(out)[1]["camera"], read(render)[1]["camera"]
    np.testing.assert_allclose(written.pose.eye, rendered.pose.eye, atol=0)
    np.testing.assert_allclose(written.pose.rotation, rendered.pose.rotation, atol=1e-12)


def test_a_photographed_panorama_is_seen_from_the_render_s_eye(tmp_path, render):
    out = tmp_path / "view.exr"
    assert main(["warp", str(_direction_pano(tmp_path / "pano.exr")), "--to", str(render), "-o", str(out), "-q",
                 "--pixel-type", "float"]) == 0
    _assert_the_render_s_view(out, render)


def test_a_panorama_lenslab_made_of_a_photograph_is_warped_to_the_render(tmp_path, render):
    """The photograph made into a cube map by lenslab (its camera recorded at the origin), then into the view."""
    cube = tmp_path / "cube.exr"
    assert main(["warp", str(_direction_pano(tmp_path / "pano.exr")), "--to", "cubemap", "-o", str(cube), "-q",
                 "--pixel-type", "float"]) == 0
    assert not np.any(read(render)[1]["camera"].pose.eye == 0)  # (the render's eye is not the origin)
    out = tmp_path / "view.exr"
    assert main(["warp", str(cube), "--to", str(render), "-o", str(out), "-q", "--pixel-type", "float"]) == 0
    _assert_the_render_s_view(out, render)
    again = tmp_path / "again.exr"  # the view, the same view as the render, warped to the render again
    assert main(["warp", str(out), "--to", str(render), "-o", str(again), "-q"]) == 0


def test_a_photographed_panorama_is_seen_from_the_eye_given(tmp_path, render):
    """``--eye`` places the view elsewhere; a panorama that records no place is the light arriving there too."""
    out = tmp_path / "view.exr"
    assert main(["warp", str(_direction_pano(tmp_path / "pano.exr")), "--to", str(render), "--eye", "1,2,3",
                 "-o", str(out), "-q", "--pixel-type", "float"]) == 0
    np.testing.assert_allclose(_centre_direction(out), _rotation(YAW, PITCH, ROLL)[:, 2], atol=0.01)
    np.testing.assert_allclose(read(out)[1]["camera"].pose.eye, [1.0, 2.0, 3.0], atol=0)
