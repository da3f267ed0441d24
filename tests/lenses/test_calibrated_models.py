"""Calibrated camera models against their sources: OpenCV's projectPoints, cv2.fisheye and cv2.omnidir
(project and undistort, also at published calibrations), the double-sphere and EUCM papers' formulas and
regions at the calibrations their authors published (Basalt), OCamCalib's cam2world, transcribed here in
float64; fields beyond 180 degrees; round trips.

Frames: OpenCV's pixel (u, v) is lenslab's (u + 0.5, v + 0.5) and OpenCV's camera (X, Y, Z) is lenslab's
(X, -Y, Z) (docs/conventions.md, "Calibrated cameras").
"""

from __future__ import annotations

import math

import cv2
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lenslab.calibfiles import read_lens
from lenslab.lenses import make_lens

#: OpenCV's answers are float64 evaluations of the same polynomials: they agree to ~1e-12 px; the
#: required accuracy is 1e-6 px
CV_TOL = 1e-6
#: round trips: the forward maps are closed forms and the inverses stop at 1e-14 of the focal length
#: (1e-11 px); 1e-9 px is the brief's bound
RT_TOL = 1e-9

W, H = 1280, 1024


def to_cv(d):
    """lenslab directions -> OpenCV camera points."""
    return np.c_[d[:, 0], -d[:, 1], d[:, 2]]


def pixel_centres(w, h, step=1):
    g = np.stack(np.meshgrid(np.arange(0, w, step) + 0.5, np.arange(0, h, step) + 0.5), -1)
    return g.reshape(-1, 2)


def sphere(n, seed=0):
    d = np.random.default_rng(seed).normal(size=(n, 3))
    return d / np.linalg.norm(d, axis=1, keepdims=True)


# -- OpenCV's pinhole with its whole distortion model ---------------------------------------------
K = np.array([[900.0, 0.0, 641.3], [0.0, 880.0, 478.9], [0.0, 0.0, 1.0]])
D12 = np.array([-0.28, 0.09, 0.001, -0.0015, -0.01, 0.02, 0.001, 0.0005, 0.001, -0.0002, 0.0007, 0.0001])
OPENCV = ("opencv:fx=900,fy=880,cx=641.3,cy=478.9,k1=-0.28,k2=0.09,p1=0.001,p2=-0.0015,k3=-0.01,k4=0.02,"
          "k5=0.001,k6=0.0005,s1=0.001,s2=-0.0002,s3=0.0007,s4=0.0001,width=1280,height=1024")


def test_opencv_matches_project_points_on_random_directions():
    lens = make_lens(OPENCV, (W, H))
    d = sphere(20000)
    xy, ok = lens.dir_to_pixel(d)
    assert ok.sum() > 2000
    ref, _ = cv2.projectPoints(to_cv(d[ok]).reshape(-1, 1, 3), np.zeros(3), np.zeros(3), K, D12)
    assert np.abs(ref.reshape(-1, 2) + 0.5 - xy[ok]).max() < CV_TOL
    # what OpenCV puts inside the image, lenslab sees too (in front of the camera, inside the fold)
    front = d[:, 2] > 0
    ref_all, _ = cv2.projectPoints(to_cv(d[front]).reshape(-1, 1, 3), np.zeros(3), np.zeros(3), K, D12)
    p = ref_all.reshape(-1, 2) + 0.5
    inside = (p[:, 0] > 1) & (p[:, 0] < W - 1) & (p[:, 1] > 1) & (p[:, 1] < H - 1)
    r = np.hypot(d[front, 0], d[front, 1]) / d[front, 2]
    assert ok[front][inside & (r < lens.distortion.fold)].all()


def test_opencv_undistorts_every_pixel_centre_to_what_project_points_maps_back():
    lens = make_lens(OPENCV, (W, H))
    xy = pixel_centres(W, H, 3)
    d, ok = lens.pixel_to_dir(xy)
    assert ok.all()
    ref, _ = cv2.projectPoints(to_cv(d).reshape(-1, 1, 3), np.zeros(3), np.zeros(3), K, D12)
    assert np.abs(ref.reshape(-1, 2) + 0.5 - xy).max() < CV_TOL
    back, ok2 = lens.dir_to_pixel(d)
    assert ok2.all() and np.abs(back - xy).max() < RT_TOL


def test_opencv_inverse_reports_what_it_cannot_solve():
    """Barrel so strong that the image corners lie beyond the fold: those pixels are invalid and zero."""
    lens = make_lens("opencv:fx=500,fy=500,cx=639.5,cy=511.5,k1=-0.6,p1=0.01,width=1280,height=1024", (W, H))
    fold = lens.distortion.fold  # d(r (1 + k1 r^2))/dr = 1 + 3 k1 r^2 = 0
    assert fold == pytest.approx(1 / math.sqrt(1.8), rel=1e-12)
    xy = np.array([[0.5, 0.5], [640.0, 512.0]])
    d, ok = lens.pixel_to_dir(xy)
    assert not ok[0] and (d[0] == 0).all() and ok[1]


# -- Kannala-Brandt (cv2.fisheye) -------------------------------------------------------------------
KB_K = np.array([[400.0, 0.0, 640.2], [0.0, 401.0, 511.7], [0.0, 0.0, 1.0]])
KB_D = np.array([0.05, -0.01, 0.003, -0.0005])
KB = "kannala-brandt:fx=400,fy=401,cx=640.2,cy=511.7,k1=0.05,k2=-0.01,k3=0.003,k4=-0.0005,width=1280,height=1024"


def test_kannala_brandt_matches_cv2_fisheye_project_points():
    lens = make_lens(KB, (W, H))
    d = sphere(20000, 1)
    xy, ok = lens.dir_to_pixel(d)
    front = ok & (d[:, 2] > 1e-3)  # cv2.fisheye divides by Z: the front hemisphere only
    ref, _ = cv2.fisheye.projectPoints(to_cv(d[front]).reshape(-1, 1, 3), np.zeros(3), np.zeros(3), KB_K, KB_D)
    assert np.abs(ref.reshape(-1, 2) + 0.5 - xy[front]).max() < CV_TOL


def test_kannala_brandt_matches_cv2_fisheye_undistort_points():
    """cv2.fisheye.undistortPoints converges up to ~80 degrees from the axis (beyond, its fixed-point
    iteration drifts: OpenCV #16926); compare there, in pixels of the undistorted plane."""
    lens = make_lens(KB, (W, H))
    xy = pixel_centres(W, H, 4)
    d, ok = lens.pixel_to_dir(xy)
    near = ok & (d[:, 2] > math.cos(math.radians(80)))
    ref = cv2.fisheye.undistortPoints((xy[near] - 0.5).reshape(-1, 1, 2), KB_K, KB_D,
                                      criteria=(cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS, 100, 1e-15))
    mine = to_cv(d[near])
    mine = mine[:, :2] / mine[:, 2:]
    assert np.abs(ref.reshape(-1, 2) - mine).max() * 400 < CV_TOL


def test_kannala_brandt_sees_beyond_90_degrees_up_to_its_monotone_range():
    lens = make_lens(KB, (W, H))
    # the end of the monotone range: 1 + 3 k1 t^2 + 5 k2 t^4 + 7 k3 t^6 + 9 k4 t^8 = 0, solved here by numpy
    k1, k2, k3, k4 = KB_D
    roots = np.roots([9 * k4, 7 * k3, 5 * k2, 3 * k1, 1.0])
    s = min(r.real for r in roots if abs(r.imag) < 1e-12 and r.real > 0)
    t_max = math.sqrt(s)
    assert lens.max_angle == pytest.approx(t_max, rel=1e-12)
    assert math.degrees(t_max) > 90
    a = np.array([0.5, 1.2, 1.6, t_max - 1e-6, t_max + 1e-6])
    d = np.c_[np.sin(a) * 0.6, np.sin(a) * 0.8, np.cos(a)]
    xy, ok = lens.dir_to_pixel(d)
    ok_model = np.abs(lens.distortion.apply(a, 0 * a)[0]) >= 0  # any finite value: the image test below
    # theta_d(theta) transcribed: the radius in OpenCV pixels along (0.6, -0.8) (y down)
    td = a * (1 + k1 * a**2 + k2 * a**4 + k3 * a**6 + k4 * a**8)
    expect = np.c_[400 * td * 0.6 + 640.2 + 0.5, 401 * td * -0.8 + 511.7 + 0.5]
    inside = (expect[:, 0] >= 0) & (expect[:, 0] <= W) & (expect[:, 1] >= 0) & (expect[:, 1] <= H)
    assert ok_model.all()
    np.testing.assert_array_equal(ok, inside & (a < t_max))
    assert np.abs(xy[ok] - expect[ok]).max() < 1e-9
    # a shorter focal length puts the whole monotone range inside the image, and nothing beyond
    wide = make_lens(KB.replace("fx=400,fy=401", "fx=100,fy=100"), (W, H))
    xy, ok = wide.dir_to_pixel(d)
    np.testing.assert_array_equal(ok, a < t_max)


# -- omnidir (cv2.omnidir) ------------------------------------------------------------------------------
@pytest.mark.parametrize("xi", [0.6, 1.0, 1.6])
def test_omnidir_matches_cv2_omnidir_project_and_undistort(xi):
    Ko = np.array([[300.0, 0.7, 640.2], [0.0, 301.0, 511.7], [0.0, 0.0, 1.0]])
    Do = np.array([[-0.05, 0.01, 0.001, -0.002]])
    lens = make_lens(f"omnidir:fx=300,fy=301,cx=640.2,cy=511.7,s=0.7,xi={xi},k1=-0.05,k2=0.01,p1=0.001,p2=-0.002,"
                     f"width={W},height={H}", (W, H))
    d = sphere(20000, 2)
    xy, ok = lens.dir_to_pixel(d)
    assert ok.sum() > 1000
    ref, _ = cv2.omnidir.projectPoints(to_cv(d[ok]).reshape(-1, 1, 3), np.zeros(3), np.zeros(3), Ko, xi, Do)
    assert np.abs(ref.reshape(-1, 2) + 0.5 - xy[ok]).max() < CV_TOL
    # undistortPoints gives the ray on the unit sphere's perspective plane (X/Z, Y/Z) for Z > 0
    px = pixel_centres(W, H, 8)
    dd, v = lens.pixel_to_dir(px)
    front = v & (dd[:, 2] > 0.05)
    und = cv2.omnidir.undistortPoints((px[front] - 0.5).reshape(-1, 1, 2), Ko, Do, np.array([[xi]]), np.eye(3))
    mine = to_cv(dd[front])
    assert np.abs(und.reshape(-1, 2) - mine[:, :2] / mine[:, 2:]).max() * 300 < CV_TOL


def test_omnidir_beyond_180_degrees_with_xi_above_1():
    xi = 1.6
    lens = make_lens(f"omnidir:fx=100,fy=100,cx=639.5,cy=511.5,xi={xi},width={W},height={H}", (W, H))
    t_max = math.acos(-1 / xi)  # where 1 + xi cos(theta) = 0: the projection folds
    a = np.array([1.0, 2.0, t_max - 1e-7, t_max + 1e-7])
    d = np.c_[np.sin(a), 0 * a, np.cos(a)]
    xy, ok = lens.dir_to_pixel(d)
    np.testing.assert_array_equal(ok, [True, True, True, False])
    # Mei's projection transcribed: u = fx sin(a) / (cos(a) + xi) + cx (+ 0.5 for lenslab's pixels)
    assert np.abs(xy[:3, 0] - (100 * np.sin(a[:3]) / (np.cos(a[:3]) + xi) + 639.5 + 0.5)).max() < 1e-9
    back, v = lens.pixel_to_dir(xy[:3])
    assert v.all() and np.abs(back - d[:3]).max() < 1e-8  # next to the fold: rounding grows as 1/sqrt(eps)


# -- double sphere and EUCM: the papers' formulas at published calibrations -------------------------------
#: Published calibrations by the double-sphere paper's authors, from their Basalt project
#: (github.com/VladyslavUsenko/basalt, data/*.json: camera 0's "intrinsics" and "resolution"): cam0 of TUM-VI's
#: 512 px stereo pair (a 195-degree fisheye) and cam0 of EuRoC, each fitted with both models
#: (tumvi_512_ds_calib.json, euroc_ds_calib.json, tumvi_512_eucm_calib.json, euroc_eucm_calib.json). Basalt puts
#: pixel centres at integers, as OpenCV does: lenslab's pixel is Basalt's + 0.5.
PUBLISHED = {
    ("double-sphere", "tumvi"): ({"fx": 158.28600034966977, "fy": 158.2743455478755, "cx": 254.96116578191653,
                                  "cy": 256.8894394501779, "xi": -0.17213086034353243, "alpha": 0.5931177593944744},
                                 (512, 512)),
    ("double-sphere", "euroc"): ({"fx": 349.7560023050409, "fy": 348.72454229977037, "cx": 365.89440762590149,
                                  "cy": 249.32995565708704, "xi": -0.2409573942178872, "alpha": 0.566996899163044},
                                 (752, 480)),
    ("eucm", "tumvi"): ({"fx": 191.14799836282189, "fy": 191.13150963902818, "cx": 254.9585771534443,
                         "cy": 256.88154645599448, "alpha": 0.6291060881178562, "beta": 1.0418067381860868},
                        (512, 512)),
    ("eucm", "euroc"): ({"fx": 460.76484651566468, "fy": 459.4051018049483, "cx": 365.8937161309615,
                         "cy": 249.33499869752445, "alpha": 0.5903365915227143, "beta": 1.127468196965374},
                        (752, 480)),
}
#: the paper's closed forms and lenslab's evaluate the same float64 expressions: they agree to ~1e-13 px and
#: ~1e-16 in a unit ray; the required accuracy is 1e-6 px
PAPER_TOL, RAY_TOL = 1e-9, 1e-12


def spec_of(model, p, w, h):
    return model + ":" + ",".join(f"{k}={v!r}" for k, v in p.items()) + f",width={w},height={h}"


def papers_w(alpha):
    """``w1`` (double sphere) or ``w`` (EUCM) of the papers' regions."""
    return alpha / (1 - alpha) if alpha <= 0.5 else (1 - alpha) / alpha


def ds_project(X, Y, Z, fx, fy, cx, cy, xi, alpha):
    """Usenko et al. 2018, the double sphere projection and its region Omega, transcribed in float64 (OpenCV's
    frame, Basalt's pixels): ``(u, v, in Omega)``."""
    d1 = np.sqrt(X * X + Y * Y + Z * Z)
    k = xi * d1 + Z
    den = alpha * np.sqrt(X * X + Y * Y + k * k) + (1 - alpha) * k
    w1 = papers_w(alpha)
    w2 = (w1 + xi) / math.sqrt(2 * w1 * xi + xi * xi + 1)
    with np.errstate(divide="ignore", invalid="ignore"):
        return fx * X / den + cx, fy * Y / den + cy, Z > -w2 * d1


def ds_unproject(u, v, fx, fy, cx, cy, xi, alpha):
    """Usenko et al. 2018, the closed-form unprojection and its region Theta, transcribed: ``(ray, in Theta)``."""
    mx, my = (u - cx) / fx, (v - cy) / fy
    r2 = mx * mx + my * my
    theta = r2 <= 1 / (2 * alpha - 1) if alpha > 0.5 else np.ones(r2.shape, bool)
    mz = (1 - alpha * alpha * r2) / (alpha * np.sqrt(np.maximum(1 - (2 * alpha - 1) * r2, 0)) + 1 - alpha)
    k = (mz * xi + np.sqrt(np.maximum(mz * mz + (1 - xi * xi) * r2, 0))) / (mz * mz + r2)
    return np.c_[k * mx, k * my, k * mz - xi], theta


def eucm_project(X, Y, Z, fx, fy, cx, cy, alpha, beta):
    """Khomutenko et al. 2016 with the region of Usenko et al. 2018, transcribed: ``(u, v, in Omega)``."""
    d = np.sqrt(beta * (X * X + Y * Y) + Z * Z)
    den = alpha * d + (1 - alpha) * Z
    with np.errstate(divide="ignore", invalid="ignore"):
        return fx * X / den + cx, fy * Y / den + cy, Z > -papers_w(alpha) * d


def eucm_unproject(u, v, fx, fy, cx, cy, alpha, beta):
    """The EUCM's closed-form unprojection and its region Theta (Usenko et al. 2018), transcribed."""
    mx, my = (u - cx) / fx, (v - cy) / fy
    r2 = mx * mx + my * my
    theta = r2 <= 1 / ((2 * alpha - 1) * beta) if alpha > 0.5 else np.ones(r2.shape, bool)
    mz = (1 - beta * alpha * alpha * r2) / (alpha * np.sqrt(np.maximum(1 - (2 * alpha - 1) * beta * r2, 0))
                                            + 1 - alpha)
    ray = np.c_[mx, my, mz]
    return ray / np.linalg.norm(ray, axis=1, keepdims=True), theta


PAPER = {"double-sphere": (ds_project, ds_unproject), "eucm": (eucm_project, eucm_unproject)}


@pytest.mark.parametrize("model,data", sorted(PUBLISHED))
def test_papers_projection_and_unprojection_at_published_calibrations(model, data):
    p, (w, h) = PUBLISHED[model, data]
    lens = make_lens(spec_of(model, p, w, h), (w, h))
    project, unproject = PAPER[model]
    d = sphere(20000, 3)
    xy, ok = lens.dir_to_pixel(d)
    u, v, omega = project(*to_cv(d).T, **p)
    ref = np.c_[u, v] + 0.5  # Basalt's pixel -> lenslab's
    inside = omega & (ref[:, 0] >= 0) & (ref[:, 0] <= w) & (ref[:, 1] >= 0) & (ref[:, 1] <= h)
    np.testing.assert_array_equal(ok, inside)
    assert ok.sum() > 2000 and np.abs(xy[ok] - ref[ok]).max() < PAPER_TOL  # EuRoC sees 1/8 of the sphere
    # every pixel centre of the calibration image: the paper's unprojection of Basalt's pixel (x - 0.5, y - 0.5)
    px = pixel_centres(w, h, 2)
    dd, valid = lens.pixel_to_dir(px)
    ray, theta = unproject(px[:, 0] - 0.5, px[:, 1] - 0.5, **p)
    assert theta.all() and valid.all()  # the whole image lies inside Theta (and Omega: next test)
    assert np.abs(to_cv(dd) - ray).max() < RAY_TOL
    # and the paper's projection takes lenslab's rays back to the pixel centres
    u, v, omega = project(*to_cv(dd).T, **p)
    assert omega.all() and np.abs(np.c_[u, v] + 0.5 - px).max() < PAPER_TOL


@pytest.mark.parametrize("model,data", sorted(PUBLISHED))
def test_papers_validity_regions_at_published_calibrations(model, data):
    """Omega, the directions the projection accepts (a cone about the axis set by xi and alpha, or alpha and
    beta), and Theta, the pixels the unprojection accepts (a disc, alpha > 0.5 in all four), at the published
    numbers. The calibration images stop short of the regions' edges (TUM-VI's corners are 120 degrees off the
    axis, Omega's edge 125), so the same lens is also put on a canvas that holds them: the principal point at
    its centre."""
    p, (w, h) = PUBLISHED[model, data]
    project, unproject = PAPER[model]
    al = p["alpha"]
    wv = papers_w(al)
    if model == "double-sphere":
        xi = p["xi"]
        t_max = math.acos(-(wv + xi) / math.sqrt(2 * wv * xi + xi * xi + 1))  # z > -w2 |x| on the unit sphere
        r_max = 1 / math.sqrt(2 * al - 1)
    else:  # z > -w sqrt(beta (x^2 + y^2) + z^2): behind the camera, tan^2 = (1 - w^2) / (w^2 beta)
        t_max = math.pi - math.atan(math.sqrt((1 - wv * wv) / (wv * wv * p["beta"])))
        r_max = 1 / math.sqrt((2 * al - 1) * p["beta"])
    assert al > 0.5 and 120 < math.degrees(t_max) < 140  # fields of view of 250 to 270 degrees
    # the calibration image lies inside both regions: its corners are the farthest from the axis
    corners = np.array([[-0.5, -0.5], [w - 0.5, -0.5], [-0.5, h - 0.5], [w - 0.5, h - 0.5]])  # lenslab's 0 and W
    ray, theta = unproject(corners[:, 0], corners[:, 1], **p)
    assert theta.all() and np.arccos(ray[:, 2]).max() < t_max
    c = math.ceil(1.1 * max(p["fx"], p["fy"]) * r_max)
    q = dict(p, cx=c - 0.5, cy=c - 0.5)
    big = make_lens(spec_of(model, q, 2 * c, 2 * c), (2 * c, 2 * c))
    # Omega's edge, along eight azimuths
    phi = np.linspace(0, 2 * math.pi, 8, endpoint=False)
    for t, want in ((t_max - 1e-7, True), (t_max + 1e-7, False)):
        d = np.c_[math.sin(t) * np.cos(phi), math.sin(t) * np.sin(phi), np.full(8, math.cos(t))]
        assert (big.dir_to_pixel(d)[1] == want).all() and (project(*to_cv(d).T, **q)[2] == want).all()
    # Basalt's own test points (test_camera.cpp: x, y in -10..10, z in -5..5): valid exactly in Omega
    g = np.stack(np.meshgrid(np.arange(-10, 11), np.arange(-10, 11), np.arange(-5, 6)), -1).reshape(-1, 3)
    g = g[np.abs(g).sum(axis=1) > 0].astype(float)
    xy, ok = big.dir_to_pixel(to_cv(g))
    u, v, omega = project(*g.T, **q)
    np.testing.assert_array_equal(ok, omega)
    assert 0 < ok.sum() < len(g) and np.abs(xy[ok] - np.c_[u, v][ok] - 0.5).max() < PAPER_TOL
    # Theta, and the pixels of Omega's edge: for the double sphere that circle lies just inside Theta's, and the
    # pixels between unproject to rays outside Omega (invalid); for the EUCM the two circles are one
    r_edge = math.hypot(*(np.r_[project(math.sin(t_max), 0.0, math.cos(t_max), **q)[:2]] - (c - 0.5))
                        / (q["fx"], q["fy"]))
    assert (r_edge < r_max * (1 - 1e-5)) if model == "double-sphere" else r_edge == pytest.approx(r_max, rel=1e-12)
    r = np.r_[np.linspace(0.0, 1.2 * r_max, 2001), r_edge * (1 - 1e-9), r_edge * (1 + 1e-9),
              0.5 * (r_edge + r_max), r_max * (1 - 1e-9), r_max * (1 + 1e-9)]
    for a in (0.3, 2.0, 4.4):  # Basalt's pixels on rays from the principal point; lenslab's are 0.5 further
        u, v = c - 0.5 + q["fx"] * r * math.cos(a), c - 0.5 + q["fy"] * r * math.sin(a)
        dd, valid = big.pixel_to_dir(np.c_[u, v] + 0.5)
        ray, theta = unproject(u, v, **q)
        np.testing.assert_array_equal(valid, theta & project(*ray.T, **q)[2])
        assert np.abs(to_cv(dd[valid]) - ray[valid]).max() < RAY_TOL
        assert valid[-5] and not valid[-4] and not valid[-1]
        assert valid[-2] == (model == "eucm") and (model == "eucm" or not valid[-3])


@pytest.mark.parametrize("data,radius,tol", [("tumvi", 200, 0.03), ("euroc", 400, 0.02)])
def test_basalts_double_sphere_and_eucm_fits_describe_one_lens(data, radius, tol):
    """Basalt fitted both models to one calibration sequence: with those numbers, lenslab's double sphere and
    EUCM send every pixel centre within ``radius`` px of the centre to the same ray (one model's ray, the
    other's pixel). The bound is the two fits' own disagreement (measured: 0.019 px TUM-VI, 0.008 px EuRoC);
    a misread parameter moves pixels by tens of px (xi's sign: 60 px on TUM-VI)."""
    (p, (w, h)), (q, _) = PUBLISHED["double-sphere", data], PUBLISHED["eucm", data]
    ds = make_lens(spec_of("double-sphere", p, w, h), (w, h))
    eu = make_lens(spec_of("eucm", q, w, h), (w, h))
    px = pixel_centres(w, h)
    px = px[np.hypot(px[:, 0] - 0.5 - p["cx"], px[:, 1] - 0.5 - p["cy"]) < radius]
    d, ok = ds.pixel_to_dir(px)
    back, ok2 = eu.dir_to_pixel(d)
    assert ok.all() and ok2.all() and np.abs(back - px).max() < tol


#: Kannala-Brandt calibrations as published, read from a Kalibr camchain (pinhole-equidistant)
KB_PUBLISHED = {
    # TUM-VI's own Kalibr calibration of cam0 at 512 px, from the dataset's camchain (quoted in full precision
    # by ORB-SLAM3's Examples/Monocular/TUM-VI.yaml): the lens of PUBLISHED[..., "tumvi"]
    "tumvi": ([190.97847715128717, 190.9733070521226, 254.93170605935475, 256.8974428996504],
              [0.0034823894022493434, 0.0007150348452162257, -0.0020532361418706202, 0.00020293673591811182],
              [512, 512]),
    # Basalt's data/t265_kb4_calib.json, camera 0 (Intel RealSense T265; Basalt's kb4 is this model)
    "t265": ([286.60144163375528, 286.4617087423328, 422.2765876951761, 395.2246466040553],
             [-0.006762412326815424, 0.045170283325720008, -0.043515167278210638, 0.008374959821591333],
             [848, 800]),
}


@pytest.mark.parametrize("data", sorted(KB_PUBLISHED))
def test_published_kannala_brandt_calibrations_match_cv2_fisheye(tmp_path, data):
    (fx, fy, cx, cy), k, (w, h) = KB_PUBLISHED[data]
    path = tmp_path / "camchain.yaml"
    path.write_text(f"cam0:\n  camera_model: pinhole\n  intrinsics: {[fx, fy, cx, cy]}\n"
                    f"  distortion_model: equidistant\n  distortion_coeffs: {k}\n  resolution: {[w, h]}\n")
    lens = read_lens(str(path))
    d = sphere(20000, 7)
    xy, ok = lens.dir_to_pixel(d)
    front = d[:, 2] > 1e-3  # cv2.fisheye divides by Z: the front hemisphere only
    ref, _ = cv2.fisheye.projectPoints(to_cv(d[front]).reshape(-1, 1, 3), np.zeros(3), np.zeros(3),
                                       np.array([[fx, 0, cx], [0, fy, cy], [0, 0, 1.0]]), np.array(k))
    ref = ref.reshape(-1, 2) + 0.5
    inside = (ref[:, 0] > 1e-3) & (ref[:, 0] < w - 1e-3) & (ref[:, 1] > 1e-3) & (ref[:, 1] < h - 1e-3)
    assert ok[front][inside].all() and inside.sum() > 5000
    assert np.abs(ref[ok[front]] - xy[front][ok[front]]).max() < CV_TOL
    # the image's corners lie beyond 90 degrees, where cv2.fisheye cannot go: theta_d transcribed
    behind = ok & ~front
    assert behind.sum() > 100
    X, Y, Z = to_cv(d[behind]).T
    rho = np.hypot(X, Y)
    t = np.arctan2(rho, Z)
    td = t * (1 + k[0] * t**2 + k[1] * t**4 + k[2] * t**6 + k[3] * t**8)
    assert np.abs(np.c_[fx * td * X / rho + cx, fy * td * Y / rho + cy] + 0.5 - xy[behind]).max() < CV_TOL


def test_double_sphere_and_eucm_see_beyond_180_degrees():
    ds = make_lens("double-sphere:fx=100,fy=100,cx=511.5,cy=511.5,xi=0.3,alpha=0.7,width=1024,height=1024", (1024, 1024))
    w1 = 0.3 / 0.7
    w2 = (w1 + 0.3) / math.sqrt(2 * w1 * 0.3 + 0.09 + 1)
    t_ds = math.acos(-w2)  # the paper's region z > -w2 |x| on the unit sphere
    eu = make_lens("eucm:fx=100,fy=100,cx=511.5,cy=511.5,alpha=0.7,beta=1.2,width=1024,height=1024", (1024, 1024))
    w = 0.3 / 0.7  # z = -w d with d = sqrt(beta sin^2 + cos^2): tan^2 = (1 - w^2) / (w^2 beta), behind
    t_eu = math.pi - math.atan(math.sqrt((1 - w * w) / (w * w * 1.2)))
    for lens, t_max in ((ds, t_ds), (eu, t_eu)):
        assert math.degrees(t_max) > 90
        a = np.array([0.3, math.pi / 2, t_max - 1e-6, t_max + 1e-6])
        d = np.c_[0 * a, np.sin(a), np.cos(a)]
        xy, ok = lens.dir_to_pixel(d)
        np.testing.assert_array_equal(ok, [True, True, True, False])
        back, v = lens.pixel_to_dir(xy[:3])
        assert v.all() and np.abs(back - d[:3]).max() < 1e-6


# -- OCamCalib ---------------------------------------------------------------------------------------
#: a calib_results.txt as OCamCalib writes it for an 848x800 fisheye (a real file's numbers)
OCAM = dict(pol=[-2.895569e02, 0.0, 1.538894e-03, -3.140320e-06, 7.206996e-09],
            invpol=[434.372025, 226.016722, -31.205890, 43.418508, 11.945692, -5.582063, 36.541804, -10.674868,
                    -55.334360, 1.105775, 43.550131, 25.374995, 4.505945],
            xc=390.949324, yc=423.714757, c=0.999134, d=-0.000325, e=-0.000071, height=800, width=848)


def ocam_spec():
    o = OCAM
    return ("ocam:pol=" + " ".join(map(str, o["pol"])) + ",invpol=" + " ".join(map(str, o["invpol"]))
            + f",xc={o['xc']},yc={o['yc']},c={o['c']},d={o['d']},e={o['e']},width=848,height=800")


def cam2world(row, col):
    """OCamCalib's cam2world (ocam_functions.c), transcribed: (row, col) -> unit ray, OCamCalib's frame."""
    o = OCAM
    invdet = 1 / (o["c"] - o["d"] * o["e"])
    xp = invdet * ((row - o["xc"]) - o["d"] * (col - o["yc"]))
    yp = invdet * (-o["e"] * (row - o["xc"]) + o["c"] * (col - o["yc"]))
    r = math.hypot(xp, yp)
    zp = sum(a * r**i for i, a in enumerate(o["pol"]))
    n = math.sqrt(xp * xp + yp * yp + zp * zp)
    return xp / n, yp / n, zp / n


def world2cam_invpol(x, y, z):
    """OCamCalib's world2cam with its fitted inverse polynomial, transcribed (an approximation)."""
    o = OCAM
    norm = math.hypot(x, y)
    theta = math.atan(z / norm)
    rho = sum(a * theta**i for i, a in enumerate(o["invpol"]))
    xx, yy = x / norm * rho, y / norm * rho
    return xx * o["c"] + yy * o["d"] + o["xc"], xx * o["e"] + yy + o["yc"]


def test_ocam_matches_ocamcalib_cam2world_at_pixel_centres():
    lens = make_lens(ocam_spec(), (848, 800))
    px = pixel_centres(848, 800, 5)
    d, ok = lens.pixel_to_dir(px)
    assert ok.all()
    for (x, y), dv in zip(px[::11], d[::11]):
        ox, oy, oz = cam2world(y - 0.5, x - 0.5)  # lenslab (x, y) = OCamCalib (col + 0.5, row + 0.5)
        # OCamCalib (x down, y right, z back) -> lenslab (right, up, forward) = (oy, -ox, -oz)
        assert np.abs(dv - (oy, -ox, -oz)).max() < 1e-12
    back, ok2 = lens.dir_to_pixel(d)
    assert ok2.all() and np.abs(back - px).max() < RT_TOL


def test_ocam_solved_forward_agrees_with_ocamcalibs_invpol_to_its_fit():
    """world2cam's invpol is a fit of the exact inverse that lenslab solves: they agree to the fit's
    error (OCamCalib fits it to well under a pixel)."""
    lens = make_lens(ocam_spec(), (848, 800))
    d = sphere(3000, 4)
    xy, ok = lens.dir_to_pixel(d)
    assert ok.sum() > 500
    err = []
    for dv, p in zip(d[ok], xy[ok]):
        row, col = world2cam_invpol(-dv[1], dv[0], -dv[2])  # lenslab -> OCamCalib frame
        err.append(max(abs(col + 0.5 - p[0]), abs(row + 0.5 - p[1])))
    assert max(err) < 0.5


# -- properties ----------------------------------------------------------------------------------------
@settings(max_examples=40, deadline=None)
@given(k1=st.floats(-0.3, 0.3), k2=st.floats(-0.1, 0.1), p1=st.floats(-0.01, 0.01), p2=st.floats(-0.01, 0.01),
       fx=st.floats(0.2, 1.0), fy=st.floats(0.0, 1.0))
def test_opencv_pixel_round_trip_property(k1, k2, p1, p2, fx, fy):
    lens = make_lens(f"opencv:fx=700,fy=700,cx=639.5,cy=511.5,k1={k1},k2={k2},p1={p1},p2={p2},width={W},height={H}",
                     (W, H))
    xy = np.array([[fx * W, fy * H]])
    d, ok = lens.pixel_to_dir(xy)
    assert np.isfinite(d).all()
    if ok[0]:
        ref, _ = cv2.projectPoints(to_cv(d).reshape(-1, 1, 3), np.zeros(3), np.zeros(3),
                                   np.array([[700.0, 0, 639.5], [0, 700.0, 511.5], [0, 0, 1]]),
                                   np.array([k1, k2, p1, p2]))
        assert np.abs(ref.reshape(-1, 2) + 0.5 - xy).max() < CV_TOL
    else:
        assert (d == 0).all()


@settings(max_examples=40, deadline=None)
@given(k=st.lists(st.floats(-0.05, 0.05), min_size=4, max_size=4), a=st.floats(0.0, 3.1), phi=st.floats(-3.2, 3.2))
def test_kannala_brandt_direction_round_trip_property(k, a, phi):
    lens = make_lens("kannala-brandt:fx=300,fy=300,cx=4095.5,cy=4095.5,k1={},k2={},k3={},k4={},width=8192,height=8192"
                     .format(*k), (8192, 8192))
    d = np.array([[math.sin(a) * math.cos(phi), math.sin(a) * math.sin(phi), math.cos(a)]])
    xy, ok = lens.dir_to_pixel(d)
    td = a * (1 + k[0] * a**2 + k[1] * a**4 + k[2] * a**6 + k[3] * a**8)  # transcribed; inside if |td| fx < 4096
    if abs(abs(td) * 300 - 4096) > 1e-6:
        assert ok[0] == (a < lens.max_angle and abs(td) * 300 * max(abs(math.cos(phi)), abs(math.sin(phi))) < 4096)
    if ok[0] and a < lens.max_angle - 1e-3:  # away from the fold, where the slope vanishes
        back, v = lens.pixel_to_dir(xy)
        assert v[0] and np.abs(lens.dir_to_pixel(back)[0] - xy).max() < RT_TOL


def test_different_image_size_scales_about_the_corner():
    lens = make_lens(OPENCV, (W, H))
    big = make_lens(OPENCV, (2 * W, 2 * H))
    assert big.fx == 1800 and big.cx + 0.5 == (641.3 + 0.5) * 2
    d = sphere(2000, 5)
    a, oka = lens.dir_to_pixel(d)
    b, okb = big.dir_to_pixel(d)
    both = oka & okb
    assert both.sum() > 100 and np.abs(b[both] - 2 * a[both]).max() < 1e-9


@settings(max_examples=30, deadline=None)
@given(model=st.sampled_from(["double-sphere", "eucm", "omnidir"]), p=st.floats(0.05, 0.95), q=st.floats(0.3, 1.6),
       fx=st.floats(0.0, 1.0), fy=st.floats(0.0, 1.0))
def test_unified_models_pixel_round_trip_property(model, p, q, fx, fy):
    """Any parameters, any pixel: a valid pixel's direction comes back to it (1e-9 px), an invalid one is 0."""
    extra = {"double-sphere": f"xi={q - 1.0},alpha={p}", "eucm": f"alpha={p},beta={q}",
             "omnidir": f"xi={q},k1={p - 0.5},p1=0.001"}[model]
    lens = make_lens(f"{model}:fx=150,fy=150,cx=319.5,cy=239.5,{extra},width=640,height=480", (640, 480))
    xy = np.array([[fx * 640, fy * 480]])
    d, ok = lens.pixel_to_dir(xy)
    assert np.isfinite(d).all()
    if not ok[0]:
        assert (d == 0).all()
        return
    back, ok2 = lens.dir_to_pixel(d)
    assert ok2[0] and np.abs(back - xy).max() < RT_TOL


def test_devernay_fov_matches_colmaps_fov_camera():
    """COLMAP's FOVCameraModel (models.h), transcribed: r_d / r_u = atan(2 r_u tan(omega/2)) / (omega r_u),
    the inverse tan(r_d omega) / (2 r_d tan(omega/2)); COLMAP's cx is OpenCV's + 0.5, lenslab's pixel is
    OpenCV's + 0.5: so lenslab's pixel is COLMAP's with the same numbers plus 0.5 minus 0.5."""
    omega = 0.9
    lens = make_lens(f"devernay-fov:fx=300,fy=301,cx=320.2,cy=239.7,omega={omega},width=640,height=480", (640, 480))
    d = sphere(4000, 6)
    xy, ok = lens.dir_to_pixel(d)
    assert ok.sum() > 500
    for (x, y, z), p in zip(to_cv(d[ok]), xy[ok]):
        u, v = x / z, y / z
        r = math.hypot(u, v)
        f = math.atan(r * 2 * math.tan(omega / 2)) / (r * omega)
        assert abs(300 * u * f + 320.2 + 0.5 - p[0]) < 1e-9 and abs(301 * v * f + 239.7 + 0.5 - p[1]) < 1e-9
    px = pixel_centres(640, 480, 7)
    dd, v = lens.pixel_to_dir(px)
    assert v.all()
    for (x, y, z), (u0, v0) in zip(to_cv(dd)[::5], px[::5]):
        mx, my = (u0 - 0.5 - 320.2) / 300, (v0 - 0.5 - 239.7) / 301
        rd = math.hypot(mx, my)
        f = math.tan(rd * omega) / (rd * 2 * math.tan(omega / 2))
        assert abs(x / z - mx * f) < 1e-12 and abs(y / z - my * f) < 1e-12
