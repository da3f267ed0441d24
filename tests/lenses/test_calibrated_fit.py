"""Fitting the calibrated models: an 8-parameter OpenCV camera from points OpenCV projected, and a
Kannala-Brandt model to a double-sphere lens."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from lenslab.fit.lens import fit_lens
from lenslab.fit.points import PointSet, fit_points

SIZE = (640, 480)
K = np.array([[520.0, 0.0, 318.7], [0.0, 515.0, 242.3], [0.0, 0.0, 1.0]])
D = np.array([-0.21, 0.06, 0.0012, -0.0008])


@pytest.mark.slow
def test_eight_parameter_opencv_camera_from_points_opencv_projected():
    rng = np.random.default_rng(1)
    d = rng.normal(size=(400, 3))
    d[:, 2] = np.abs(d[:, 2]) + 1.2
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    ip, _ = cv2.projectPoints(d.reshape(-1, 1, 3), np.zeros(3), np.zeros(3), K, D)
    ip = ip.reshape(-1, 2)
    # marks at least 40 px inside the image: a start far from the answer moves points near the edge out
    # of the image, where they count as unseen
    inside = (ip[:, 0] > 40) & (ip[:, 0] < 600) & (ip[:, 1] > 40) & (ip[:, 1] < 440)
    pts = PointSet(ip[inside] + 0.5, np.c_[d[inside, 0], -d[inside, 1], d[inside, 2]],
                   [f"p{i}" for i in range(int(inside.sum()))])
    fit = fit_points(pts, "opencv:fx=450,fy=450,cx=319.5,cy=239.5,width=640,height=480", SIZE,
                     free="fx,fy,cx,cy,k1,k2,p1,p2")
    lens = fit.lens
    # exact points: the optimiser's tolerance (1e-10 relative) leaves ~1e-8 in the parameters
    got = [lens.fx, lens.fy, lens.cx, lens.cy, lens.k1, lens.k2, lens.p1, lens.p2]
    np.testing.assert_allclose(got, [520, 515, 318.7, 242.3, *D], rtol=1e-6, atol=1e-7)
    assert np.max(fit.residuals) < 1e-6


@pytest.mark.slow
def test_kannala_brandt_fitted_to_a_double_sphere_lens():
    """A 200-degree-class double-sphere lens (xi = -0.2, alpha = 0.6) is a Kannala-Brandt lens to a few
    thousandths of a pixel: numpy's least squares of theta_d(theta) along the diagonal gives
    f = 249.993, k1 = -0.01020 (0.0026 px); the fit (with bounds on the scale of each coefficient) finds it."""
    src = "double-sphere:fx=200,fy=200,cx=319.5,cy=255.5,xi=-0.2,alpha=0.6,width=640,height=512"
    fit = fit_lens(src, "kannala-brandt:fx=240,fy=240,cx=319.5,cy=255.5,p1=0,p2=0,s1=0,s2=0,s3=0,s4=0",
                   size=(640, 512), free="fx,fy,k1,k2,k3,k4", global_start=None,
                   bounds="k1=-0.1:0.1,k2=-0.02:0.02,k3=-0.005:0.005,k4=-0.001:0.001")
    assert fit.ok, fit.reason()
    assert fit.max < 0.05  # px over the image; the least-squares polynomial reaches 0.0026 px
    assert fit.lens.fx == pytest.approx(249.993, abs=0.05) and fit.lens.k1 == pytest.approx(-0.0102, abs=2e-4)
