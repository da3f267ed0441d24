"""The undistort / redistort workflow of VFX with a calibration file, through ``lenslab warp``; a traced
image through an ``opencv`` lens against the warp; fitting the calibrated models."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main
from lenslab.io import read, write
from lenslab.lenses import Camera, make_lens

PLATE = (640, 512)
CAL = """\
cam0:
  camera_model: pinhole
  intrinsics: [330.0, 331.0, 321.3, 254.7]
  distortion_model: equidistant
  distortion_coeffs: [0.03, -0.01, 0.002, -0.0002]
  resolution: [640, 512]
"""


def coordinate_plate(w, h):
    """An image whose channels are its own pixel-centre coordinates (x, y, 1): a linear function, which
    bilinear interpolation reproduces exactly, so what comes back after a round trip is the geometry."""
    x, y = np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5)
    return np.dstack([x, y, np.ones_like(x)]).astype(np.float32)


def test_undistort_and_redistort_round_trip_through_the_command(tmp_path):
    cal = tmp_path / "camchain.yaml"
    cal.write_text(CAL)
    plate = tmp_path / "plate.exr"
    write(plate, coordinate_plate(*PLATE), pixel_type="float")
    flat = tmp_path / "flat.exr"
    back = tmp_path / "back.exr"
    assert main(["warp", str(plate), "-o", str(flat), "--from", str(cal), "--to", "perspective:fov=110",
                 "--size", "1024x820", "--pixel-type", "float", "--quiet"]) == 0
    assert main(["warp", str(flat), "-o", str(back), "--from", "perspective:fov=110", "--to", str(cal),
                 "--pixel-type", "float", "--quiet"]) == 0
    img, _ = read(back)
    assert img.shape[:2] == (PLATE[1], PLATE[0])  # the calibration's size by default
    alpha = img[..., 3] if img.shape[2] == 4 else np.ones(img.shape[:2], np.float32)
    from scipy.ndimage import binary_erosion

    # pixels whose whole bilinear neighbourhood, both ways, is inside both images (3 px from any edge)
    full = binary_erosion(alpha > 0.999, iterations=3, border_value=0)
    assert full.mean() > 0.5  # the perspective view covers most of the plate
    x, y = np.meshgrid(np.arange(PLATE[0]) + 0.5, np.arange(PLATE[1]) + 0.5)
    # colour is premultiplied by alpha; where alpha is 1 the channels are the plate coordinates again.
    # Tolerance 0.01 px: the warp's maps are good to 1/200 px, bilinear reproduces the linear plate exactly
    # on the way out and, on the way back, interpolates a smooth map whose curvature over one pixel is
    # below 1e-2 px; the EXR files hold float32
    err = np.maximum(np.abs(img[..., 0] - x), np.abs(img[..., 1] - y))[full]
    assert err.max() < 0.01, err.max()  # measured 0.0016 px


def test_round_trip_geometry_is_exact_where_both_lenses_see():
    """Lens level: plate pixel -> direction -> perspective pixel -> direction -> plate pixel, to 1e-9 px."""
    src = make_lens("kannala-brandt:fx=330,fy=331,cx=321.3,cy=254.7,k1=0.03,k2=-0.01,k3=0.002,k4=-0.0002,"
                    "width=640,height=512", PLATE)
    dst = make_lens("perspective:fov=110", (1024, 820))
    x, y = np.meshgrid(np.arange(PLATE[0]) + 0.5, np.arange(PLATE[1]) + 0.5)
    xy = np.c_[x.ravel(), y.ravel()]
    d, ok = src.pixel_to_dir(xy)
    p, ok2 = dst.dir_to_pixel(d)
    d2, ok3 = dst.pixel_to_dir(p)
    q, ok4 = src.dir_to_pixel(d2)
    both = ok & ok2 & ok3 & ok4
    assert both.mean() > 0.5 and np.abs(q[both] - xy[both]).max() < 1e-9


def test_traced_image_through_an_opencv_lens_matches_the_warp():
    """The tracer takes its primary rays from Camera.rays, the warp its map from the same lens: a traced
    render of an environment panorama through an ``opencv`` lens is the warp of that panorama."""
    import tracer
    from tracer.envlight import EquirectEnvironment
    from tracer.scene import merge_meshes

    from lenslab.warp import warp

    rng = np.random.default_rng(0)
    x = np.linspace(0, 6 * np.pi, 512)
    pano = (1.0 + 0.5 * np.sin(x)[None, :, None] * np.cos(x[:256] / 2)[:, None, None]
            + 0.1 * rng.random((256, 512, 3))).astype(np.float32)
    lens = make_lens("opencv:fx=150,fy=150,cx=79.5,cy=59.5,k1=-0.2,k2=0.05,p1=0.001,width=160,height=120", (160, 120))
    cam = Camera(lens)
    traced = tracer.render(merge_meshes([], environment=EquirectEnvironment(pano)), cam, spp=1, seed=None).image
    warped, alpha = warp(pano, Camera.from_spec("equirect", (512, 256)), cam, filter="nearest", exact_map=True)
    assert (alpha == 1).all()
    # both take the panorama texel each ray lands in (the tracer's environment lookup is nearest): the
    # same texels, but for rays within float32 rounding (1e-4 texel) of a texel edge, where the warp's
    # float32 map may round across it: at most a few pixels in 19200
    same = (traced == warped[..., :3]).all(axis=-1)
    assert same.mean() > 0.999
