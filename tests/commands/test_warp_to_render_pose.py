"""``lenslab warp IN --to render.exr`` makes the view that ``render.exr`` was traced through: its lens and its
orientation (it used to take the lens alone, looking down +z), and its eye when the source records its own
camera (both placed in one world). Options that would turn the view (--yaw, --pitch, --roll, --look-at) are a
usage error, since it cannot be told whether they turn the render's view or the world's.

The source is a panorama whose pixels hold their own world direction (an analytic field), so the output's centre
tells where the view looks; the expected direction is the forward axis of the pose given to ``tracer render``,
from the rotation ``Ry(yaw) Rx(-pitch) Rz(roll)`` of docs/conventions.md, transcribed here in float64.
"""

from __future__ import annotations

import contextlib
import io

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import read, write
from lenslab.lenses import Camera, Pose, make_lens
from tracer.cli import main as tracer

YAW, PITCH, ROLL = 30.0, -15.0, 5.0
SIZE = (32, 24)


def _rotation(yaw, pitch, roll) -> np.ndarray:
    """Camera -> world, degrees: yaw turns right about +y, pitch up about +x, roll about +z (conventions)."""
    y, p, r = np.radians([yaw, pitch, roll])
    ry = np.array([[np.cos(y), 0, np.sin(y)], [0, 1, 0], [-np.sin(y), 0, np.cos(y)]])
    rx = np.array([[1, 0, 0], [0, np.cos(-p), -np.sin(-p)], [0, np.sin(-p), np.cos(-p)]])
    rz = np.array([[np.cos(r), -np.sin(r), 0], [np.sin(r), np.cos(r), 0], [0, 0, 1]])
    return ry @ rx @ rz


@pytest.fixture(scope="module")
def render(tmp_path_factory):
    """A small render of the Cornell box through a turned perspective lens, as a user makes one."""
    path = tmp_path_factory.mktemp("render") / "render.exr"
    assert tracer(["render", "--camera", "perspective:fov=60", "--size", f"{SIZE[0]}x{SIZE[1]}", "--spp", "1",
                   "--yaw", str(YAW), "--pitch", str(PITCH), "--roll", str(ROLL), "-o", str(path), "-q"]) == 0
    return path


def _direction_pano(path, eye=None):
    """A 512x256 equirect whose pixels hold (d + 1) / 2 of their world direction d, recording its camera at
    ``eye`` (None: no camera recorded)."""
    lens = make_lens("equirect", (512, 256))
    ys, xs = np.mgrid[0:256, 0:512] + 0.5
    d, _ = lens.pixel_to_dir(np.stack([xs, ys], axis=-1))
    camera = None if eye is None else Camera(lens, Pose(np.eye(3), np.asarray(eye, dtype=np.float64)))
    write(path, ((d + 1) / 2).astype(np.float32), camera=camera, pixel_type="float")
    return path


def _centre_direction(path) -> np.ndarray:
    image = read(path)[0][..., :3].astype(np.float64)
    h, w = image.shape[:2]
    d = image[h // 2 - 1:h // 2 + 1, w // 2 - 1:w // 2 + 1].mean(axis=(0, 1)) * 2 - 1  # the 4 pixels round the axis
    return d / np.linalg.norm(d)


def test_the_render_records_the_pose_given(render):
    camera = read(render)[1]["camera"]
    np.testing.assert_allclose(camera.pose.rotation, _rotation(YAW, PITCH, ROLL), atol=1e-12)


def test_the_view_looks_where_the_render_looked(tmp_path, render):
    """Tolerance 0.01: the centre's four pixels lie symmetrically about the axis (about 1.9 degrees apart), and a
    bilinear read of a direction field sampled every 0.7 degrees errs far less; looking down +z, as the warp did,
    misses by 0.5."""
    eye = read(render)[1]["camera"].pose.eye
    src = _direction_pano(tmp_path / "pano.exr", eye)
    out = tmp_path / "view.exr"
    assert main(["warp", str(src), "--to", str(render), "-o", str(out), "-q", "--pixel-type", "float"]) == 0
    forward = _rotation(YAW, PITCH, ROLL)[:, 2]
    np.testing.assert_allclose(_centre_direction(out), forward, atol=0.01)
    written = read(out)[1]["camera"]
    assert written.size == SIZE
    np.testing.assert_allclose(written.pose.rotation, _rotation(YAW, PITCH, ROLL), atol=1e-12)
    np.testing.assert_allclose(written.pose.eye, eye, atol=0)


def test_a_panorama_that_records_no_place_is_seen_from_its_own_eye(tmp_path, render):
    src = _direction_pano(tmp_path / "pano.exr")  # no camera: a photographed panorama
    out = tmp_path / "view.exr"
    assert main(["warp", str(src), "--to", str(render), "-o", str(out), "-q", "--pixel-type", "float"]) == 0
    np.testing.assert_allclose(_centre_direction(out), _rotation(YAW, PITCH, ROLL)[:, 2], atol=0.01)


def test_a_source_recorded_elsewhere_is_refused_for_parallax(tmp_path, render):
    eye = read(render)[1]["camera"].pose.eye + np.array([0.0, 0.0, 0.2])
    src = _direction_pano(tmp_path / "pano.exr", eye)
    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        code = main(["warp", str(src), "--to", str(render), "-o", str(tmp_path / "view.exr"), "-q"])
    assert code == 1 and "parallax" in err.getvalue()
    assert not (tmp_path / "view.exr").exists()


@pytest.mark.parametrize("option", [["--yaw", "10"], ["--pitch", "-5"], ["--roll", "2"], ["--look-at", "0,0,1"]])
def test_options_that_turn_the_view_are_refused(tmp_path, render, option):
    src = _direction_pano(tmp_path / "pano.exr")
    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        code = main(["warp", str(src), "--to", str(render), "-o", str(tmp_path / "view.exr"), *option])
    assert code == 2
    text = err.getvalue()
    assert text.count("\n") == 1 and option[0] in text and f"yaw {YAW:g}, pitch {PITCH:g}, roll {ROLL:g}" in text
    assert "--to perspective:fov=60" in text


def test_an_st_map_to_the_render_takes_its_orientation(tmp_path, render):
    """``lenslab stmap --from equirect --to render.exr``: the map's centre reads the source where the render
    looked, x = W (0.5 + lon / 360) and y = H (0.5 - lat / 180) of the forward direction (lenslab's equirect)."""
    out = tmp_path / "map.exr"
    assert main(["stmap", "--from", "equirect", "--source-size", "512x256", "--to", str(render),
                 "--size", f"{SIZE[0]}x{SIZE[1]}", "-o", str(out), "-q"]) == 0
    st = read(out)[0].astype(np.float64)
    h, w = st.shape[:2]
    s, t = st[h // 2 - 1:h // 2 + 1, w // 2 - 1:w // 2 + 1, :2].mean(axis=(0, 1))
    f = _rotation(YAW, PITCH, ROLL)[:, 2]
    lon, lat = np.degrees(np.arctan2(f[0], f[2])), np.degrees(np.arcsin(f[1]))
    np.testing.assert_allclose([s, 1 - t], [0.5 + lon / 360, 0.5 - lat / 180], atol=0.005)
