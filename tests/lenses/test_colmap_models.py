"""Every COLMAP camera model against pycolmap (the test oracle): projection and unprojection.

For each model a camera line is written to ``cameras.txt``, read by lenslab, and compared with pycolmap's
``Camera`` built from the same numbers: 2000 random rays projected by both (``img_from_cam`` against
lenslab's ``dir_to_pixel``), and 2000 random pixels unprojected by lenslab whose rays pycolmap projects
back onto the pixel they came from (and whose bearings equal pycolmap's ``cam_ray_from_img``).
The tolerance, 1e-6 px, is float64 arithmetic through a few transcendental functions and (for the
iteratively inverted models) the convergence of two different solvers, at focal lengths of a few
hundred px: both sides agree to ~1e-9 px where they converge.
"""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.calibfiles import read_lens, write_lens
from lenslab.calibfiles.colmap_models import MODELS

pycolmap = pytest.importorskip("pycolmap")

W, H = 640, 480
TOL_PX = 1e-6
N = 2000

#: one camera per model, parameters of a real-looking calibration (COLMAP's order, COLMAP's pixels)
CAMERAS = {
    "SIMPLE_PINHOLE": [500.0, 321.5, 238.25],
    "PINHOLE": [510.0, 495.0, 318.0, 242.5],
    "SIMPLE_RADIAL": [480.0, 322.0, 241.0, -0.08],
    "RADIAL": [480.0, 322.0, 241.0, -0.08, 0.012],
    "OPENCV": [505.0, 498.0, 319.5, 240.7, -0.11, 0.03, 0.0008, -0.0005],
    "FULL_OPENCV": [505.0, 498.0, 319.5, 240.7, -0.11, 0.03, 0.0008, -0.0005, 0.002, 0.01, 0.002, 0.0005],
    "SIMPLE_FISHEYE": [200.0, 321.0, 239.0],
    "FISHEYE": [203.0, 198.5, 321.0, 239.0],
    "SIMPLE_RADIAL_FISHEYE": [200.0, 321.0, 239.0, 0.02],
    "RADIAL_FISHEYE": [200.0, 321.0, 239.0, 0.02, -0.004],
    "OPENCV_FISHEYE": [203.0, 198.5, 321.0, 239.0, 0.03, -0.01, 0.002, -0.0003],
    "THIN_PRISM_FISHEYE": [203.0, 198.5, 321.0, 239.0, 0.03, -0.01, 0.0004, -0.0003, 0.002, -0.0003, 0.0005,
                           -0.0004],
    "RAD_TAN_THIN_PRISM_FISHEYE": [241.6, 241.5, 318.7, 240.3, 0.41, -0.39, -0.12, 1.56, -1.55, 0.43,
                                   0.0006, -0.0002, -0.0005, 0.00003, 0.0003, -0.00005],
    "FOV": [400.0, 398.0, 320.5, 240.5, 0.9],
    "SIMPLE_DIVISION": [420.0, 319.0, 241.0, -0.15],
    "DIVISION": [420.0, 415.0, 319.0, 241.0, 0.2],
    "EUCM": [260.0, 258.0, 320.0, 240.0, 0.63, 1.05],
    "EQUIRECTANGULAR": [float(W), float(H)],
}


def test_every_pycolmap_model_is_covered():
    """The table holds every model pycolmap has (and the test one camera of each)."""
    names = {m for m in pycolmap.CameraModelId.__members__ if m != "INVALID"}
    assert names == set(MODELS) == set(CAMERAS)


def oracle(model):
    cam = pycolmap.Camera.create_from_model_name(1, model, 100.0, W, H)
    cam.params = CAMERAS[model]
    return cam


def lenslab_lens(tmp_path, model):
    path = tmp_path / "cameras.txt"
    path.write_text(f"# Camera list\n1 {model} {W} {H} " + " ".join(repr(p) for p in CAMERAS[model]) + "\n")
    return read_lens(str(path))


def lenslab_to_colmap(d):
    """lenslab's camera frame (y up) to COLMAP's (OpenCV's, y down)."""
    return d * np.array([1.0, -1.0, 1.0])


def random_pixels(rng, n):
    return np.column_stack([rng.uniform(0.0, W, n), rng.uniform(0.0, H, n)])


@pytest.mark.parametrize("model", sorted(CAMERAS))
def test_projection_matches_pycolmap(tmp_path, model):
    lens = lenslab_lens(tmp_path, model)
    cam = oracle(model)
    rng = np.random.default_rng(25)
    # rays the camera sees: pycolmap's own rays through random pixels, jittered, so every part of the
    # image is covered (the jitter keeps the rays independent of lenslab's inverse)
    rays = cam.cam_ray_from_img(random_pixels(rng, 4 * N))
    rays = rays + rng.normal(0.0, 1e-3, rays.shape)
    rays /= np.linalg.norm(rays, axis=1, keepdims=True)
    if model != "EQUIRECTANGULAR":
        rays = rays[rays[:, 2] > 0.05]  # pycolmap projects the front half-space only
    want = cam.img_from_cam(rays)
    inside = np.isfinite(want).all(axis=1) & (want[:, 0] > 0) & (want[:, 0] < W) & (want[:, 1] > 0) & (want[:, 1] < H)
    rays, want = rays[inside][:N], want[inside][:N]
    assert len(rays) == N
    got, ok = lens.dir_to_pixel(lenslab_to_colmap(rays))
    assert ok.all()
    err = np.abs(got - want).max()
    assert err < TOL_PX, f"{model}: projection differs by up to {err:.3g} px"


@pytest.mark.parametrize("model", sorted(CAMERAS))
def test_unprojection_matches_pycolmap(tmp_path, model):
    lens = lenslab_lens(tmp_path, model)
    cam = oracle(model)
    rng = np.random.default_rng(52)
    xy = random_pixels(rng, 3 * N)
    d, ok = lens.pixel_to_dir(xy)
    assert ok.all()
    rays = lenslab_to_colmap(d)
    front = rays[:, 2] > 0.05 if model != "EQUIRECTANGULAR" else np.ones(len(rays), bool)
    xy, rays = xy[front][:N], rays[front][:N]
    assert len(xy) == N
    back = cam.img_from_cam(rays)
    err = np.abs(back - xy).max()
    assert err < TOL_PX, f"{model}: lenslab's rays land up to {err:.3g} px off in pycolmap"
    # and they are pycolmap's own bearings (angle in units of a pixel at the focal length) wherever
    # pycolmap's iterative undistortion converges: pycolmap 4.2.1 returns rays for the fisheye models'
    # outer field that its own img_from_cam sends 100 px and more away from the pixel (a quarter of
    # this image for OPENCV_FISHEYE); there the projection check above is the oracle
    want = cam.cam_ray_from_img(xy)
    converged = np.abs(cam.img_from_cam(want) - xy).max(axis=1) < TOL_PX
    assert converged.sum() > N // 2
    f = max(cam.focal_length_x, cam.focal_length_y) if model != "EQUIRECTANGULAR" else W / (2 * np.pi)
    angle = np.linalg.norm(want - rays, axis=1)[converged]  # the chord: the angle to 1e-16 at these sizes
    assert (angle * f).max() < TOL_PX


@pytest.mark.parametrize("model", sorted(CAMERAS))
def test_cameras_txt_writes_the_model_back(tmp_path, model):
    """Written back, the camera is the same COLMAP model with the same numbers (the smallest model that
    holds it: a zero term drops to a smaller model only where pycolmap's projection is the same)."""
    lens = lenslab_lens(tmp_path, model)
    out = tmp_path / "out" / "cameras.txt"
    out.parent.mkdir()
    write_lens(str(out), lens)
    line = [l for l in out.read_text().splitlines() if not l.startswith("#")][0].split()
    assert line[1] == model
    np.testing.assert_allclose([float(p) for p in line[4:]], CAMERAS[model], rtol=1e-14, atol=1e-12)
