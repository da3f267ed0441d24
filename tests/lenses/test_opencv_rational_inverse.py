"""The rational OpenCV model's inverse accepts every pixel its forward map reaches, up to the fold.

The camera's fold (where the radial map r R(r) stops increasing) lies near the image corners; its
tangential terms carry valid rays slightly beyond the radial map's largest radius, where the inverse
used to give up (about 2000 pixels just inside the fold, e.g. (129.5, 128.5), were invalid)."""

from __future__ import annotations

import cv2
import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from lenslab.lenses import make_lens

SPEC = ("opencv:fx=620,fy=621,cx=640,cy=399.7,k1=0.42,k2=-0.05,p1=0.0007,p2=-0.0004,k3=0.002,k4=0.78,"
        "k5=0.011,k6=0.0009,width=1280,height=800")
K = np.array([[620.0, 0, 640.0], [0, 621.0, 399.7], [0, 0, 1]])
D = np.array([0.42, -0.05, 0.0007, -0.0004, 0.002, 0.78, 0.011, 0.0009])
LENS = make_lens(SPEC, (1280, 800))
FOLD = LENS.distortion.fold  # undistorted radius of the fold, on the plane z = 1


def cv_pixel(d):
    """cv2.projectPoints' pixel of lenslab directions (OpenCV: y down, pixel centres at integers)."""
    pts = np.c_[d[:, 0], -d[:, 1], d[:, 2]].reshape(-1, 1, 3)
    uv, _ = cv2.projectPoints(pts, np.zeros(3), np.zeros(3), K, D)
    return uv.reshape(-1, 2) + 0.5


@settings(max_examples=300, deadline=None)
@given(st.floats(0.0, 1.0, exclude_max=True), st.floats(0.0, 2 * np.pi), st.floats(0.9, 1.0))
def test_every_ray_the_forward_map_reaches_comes_back(t, phi, edge):
    # rays out to the fold, most of them in its last 10 % (the band that was refused)
    r = FOLD * (edge if t < 0.7 else t)
    d = np.array([[r * np.cos(phi), r * np.sin(phi), 1.0]])
    d /= np.linalg.norm(d)
    xy, ok = LENS.dir_to_pixel(d)
    if not ok[0]:  # outside the image, or where the tangential terms fold the map (Jacobian <= 0)
        return
    # the forward map is OpenCV's (1e-7 px: cv2 computes in float64 too)
    assert np.abs(xy - cv_pixel(d)).max() < 1e-7
    back, valid = LENS.pixel_to_dir(xy)
    assert valid[0], xy
    # 1e-9 rad: the 2-D Newton stops at a residual of 1e-14 (normalised plane); near the fold the map's
    # Jacobian is small (the radial derivative goes to 0 there), which magnifies that residual
    assert np.linalg.norm(back[0] - d[0]) < 1e-9


def test_the_issue_pixel_is_valid_and_maps_back():
    d, ok = LENS.pixel_to_dir([[129.5, 128.5]])
    assert ok[0]
    assert np.abs(cv_pixel(d) - [[129.5, 128.5]]).max() < 1e-7  # OpenCV sends that ray to that pixel


def test_a_dense_sweep_of_valid_rays_all_come_back():
    rng = np.random.default_rng(0)
    r = FOLD * np.sqrt(rng.random(200000))
    phi = rng.random(200000) * 2 * np.pi
    d = np.c_[r * np.cos(phi), r * np.sin(phi), np.ones_like(r)]
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    xy, ok = LENS.dir_to_pixel(d)
    back, valid = LENS.pixel_to_dir(xy[ok])
    assert ok.sum() > 100000 and valid.all()
    assert np.abs(back - d[ok]).max() < 1e-9
