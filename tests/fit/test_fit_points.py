"""Calibration from points: robust recovery with outliers, per-point residuals, the CSV forms."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.errors import FitError
from lenslab.fit.points import PointSet, fit_points, lonlat_to_dir, read_points
from lenslab.lenses import Camera, Pose, make_lens

SIZE = (640, 480)


def synthetic(spec: str, ypr=(0.0, 0.0, 0.0), n=80, outliers=0.1, seed=3, noise=0.0):
    """Points seen by a known camera, a fraction of them moved by 20..150 px (gross mistakes)."""
    rng = np.random.default_rng(seed)
    cam = Camera(make_lens(spec, SIZE), Pose.from_ypr(*ypr))
    xy = np.empty((0, 2))
    while len(xy) < n:  # pixels the lens maps (inside a fisheye's circle)
        cand = rng.uniform((5, 5), (SIZE[0] - 5, SIZE[1] - 5), (n, 2))
        ok = cam.lens.pixel_to_dir(cand)[1]
        xy = np.concatenate([xy, cand[ok]])[:n]
    _, d, _ = cam.pixel_to_world(xy)
    bad = rng.choice(n, int(round(outliers * n)), replace=False)
    moved = xy.copy()
    moved[bad] += rng.uniform(20, 150, (len(bad), 2)) * rng.choice([-1, 1], (len(bad), 2))
    moved += rng.normal(0, noise, moved.shape) if noise else 0.0
    return cam, PointSet(moved, d, [f"p{i}" for i in range(n)]), np.sort(bad)


@pytest.mark.parametrize("loss", ["cauchy", "huber", "soft_l1"])
def test_ten_percent_outliers_do_not_spoil_the_calibration(loss):
    cam, pts, bad = synthetic("fisheye:fov=170,mapping=equisolid", ypr=(8.0, -4.0, 2.5))
    fit = fit_points(pts, "fisheye:mapping=equisolid,fov=150", SIZE, free="fov", pose=True, loss=loss)
    # the outliers are found, exactly, and only they
    assert np.array_equal(np.flatnonzero(~fit.inlier), bad)
    # the inliers are exact, so the least-squares refit recovers the camera exactly (1e-6 deg: far
    # below the 1e-3 px the residual check allows, and well above the optimiser's 1e-10 tolerance)
    assert fit.lens.fov == pytest.approx(170, abs=1e-6)
    assert fit.camera.pose.ypr == pytest.approx((8.0, -4.0, 2.5), abs=1e-6)
    assert fit.max < 1e-3 and fit.ok
    assert np.all(fit.residuals[bad] > 15)  # each outlier shows its own large residual


def test_plain_least_squares_is_pulled_away_by_the_same_outliers():
    """The reason for the robust loss: without it, one pass of least squares is off by degrees."""
    cam, pts, bad = synthetic("perspective:fov=75", ypr=(5.0, 2.0, -1.0), seed=5)
    robust = fit_points(pts, "perspective:fov=60", SIZE, free="fov", pose=True, loss="cauchy")
    plain = fit_points(pts, "perspective:fov=60", SIZE, free="fov", pose=True, loss="linear", outlier=1e9)
    assert robust.lens.fov == pytest.approx(75, abs=1e-6)
    assert abs(plain.lens.fov - 75) > 0.1  # degrees; a tenth of a degree is many pixels here


def test_noisy_points_give_a_residual_of_the_noise():
    cam, pts, bad = synthetic("brown:k1=-0.08,k2=0.01,fov=70", n=150, outliers=0.1, noise=0.3, seed=11)
    fit = fit_points(pts, "brown", SIZE, scale=0.5)
    assert set(np.flatnonzero(~fit.inlier)) == set(bad)
    # 0.3 px Gaussian noise per axis: the reprojection RMS is about 0.3 * sqrt(2) = 0.42 px
    assert 0.3 < fit.rms < 0.55
    # the parameters come back to within what that noise allows
    values = fit.lens.param_values()
    assert values["k1"] == pytest.approx(-0.08, abs=0.01) and values["fov"] == pytest.approx(70, abs=0.3)


def test_same_calibration_twice():
    _, pts, _ = synthetic("fisheye:fov=190,mapping=equidistant", ypr=(3, 2, 1))
    a = fit_points(pts, "fisheye:mapping=equidistant", SIZE, pose=True)
    b = fit_points(pts, "fisheye:mapping=equidistant", SIZE, pose=True)
    assert a.lens.spec() == b.lens.spec() and np.array_equal(a.residuals, b.residuals)


def test_report_lists_every_point_and_flags_outliers():
    _, pts, bad = synthetic("perspective:fov=75", n=20, outliers=0.1)
    fit = fit_points(pts, "perspective", SIZE)
    lines = fit.report()
    rows = [ln for ln in lines if ln.startswith("  ") and "p" in ln.split()[0]]
    assert len(rows) == 20
    assert sum("outlier" in r for r in rows) == len(bad) == 2


# -- the CSV forms ------------------------------------------------------------------------------
def test_csv_with_directions(tmp_path):
    cam, pts, _ = synthetic("perspective:fov=75", n=12, outliers=0.0)
    path = tmp_path / "pts.csv"
    rows = ["# measured by hand", "x,y,dx,dy,dz"] + [
        f"{x:.17g},{y:.17g},{2 * dx:.17g},{2 * dy:.17g},{2 * dz:.17g}" for (x, y), (dx, dy, dz) in zip(pts.xy, pts.dirs)]
    path.write_text("\n".join(rows) + "\n")
    back = read_points(path)
    assert np.array_equal(back.xy, pts.xy)
    assert np.allclose(back.dirs, pts.dirs, atol=1e-15)  # unit length restored
    assert back.labels[0] == "line 3"
    fit = fit_points(back, "perspective", SIZE)
    assert fit.lens.fov == pytest.approx(75, abs=1e-6)


def test_csv_with_longitude_and_latitude(tmp_path):
    lon = np.array([0.0, 30.0, -30.0, 10.0, -15.0, 25.0])
    lat = np.array([0.0, 10.0, -12.0, 20.0, 5.0, -20.0])
    cam = Camera(make_lens("fisheye:fov=180,mapping=stereographic", SIZE))
    xy, ok = cam.world_to_pixel(lonlat_to_dir(lon, lat))
    assert ok.all()
    path = tmp_path / "stars.csv"
    path.write_text("x,y,lon,lat\n" + "".join(f"{x:.17g},{y:.17g},{a:.17g},{b:.17g}\n" for (x, y), a, b in zip(xy, lon, lat)))
    fit = fit_points(read_points(path), "fisheye:mapping=stereographic", SIZE)
    assert fit.lens.fov == pytest.approx(180, abs=1e-6)


def test_csv_with_pixel_pairs_from_a_known_camera(tmp_path):
    source = Camera.from_spec("equirect", (720, 360))
    unknown = Camera(make_lens("distortion:k1=-0.15,fov=80", SIZE), Pose.from_ypr(20, 5, 0))
    rng = np.random.default_rng(0)
    xy = rng.uniform((10, 10), (630, 470), (30, 2))
    _, d, _ = unknown.pixel_to_world(xy)
    src_xy, ok = source.world_to_pixel(d)
    assert ok.all()
    path = tmp_path / "pairs.csv"
    path.write_text("src_x,src_y,x,y\n" + "".join(f"{a:.17g},{b:.17g},{x:.17g},{y:.17g}\n" for (a, b), (x, y) in zip(src_xy, xy)))
    fit = fit_points(read_points(path, source), "distortion:fov=70", SIZE, free="k1,fov", pose=True)
    assert fit.lens.k1 == pytest.approx(-0.15, abs=1e-6)
    assert fit.camera.pose.ypr[0] == pytest.approx(20, abs=1e-5)


@pytest.mark.parametrize("text,match", [
    ("", "no points"),
    ("x,y,dx,dy,dz\n1,2,3\n", "header names 5 columns"),
    ("1,2,0,0,1\n1,2,0,0\n", "different numbers of columns"),
    ("1,2,a,0,1\n", "expected numbers"),
    ("1,2,0,0,0\n", "non-zero direction"),
    ("x,y,foo,bar\n1,2,3,4\n", "no direction columns"),
    ("src_x,src_y,x,y\n1,2,3,4\n", "--source"),
    ("1,2,3\n", "without a header"),
])
def test_bad_csv_files_are_explained(tmp_path, text, match):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(FitError, match=match):
        read_points(path)


def test_too_few_points_and_bad_options_are_refused():
    _, pts, _ = synthetic("perspective:fov=75", n=3, outliers=0.0)
    with pytest.raises(FitError, match="cannot determine"):
        fit_points(pts, "perspective", SIZE, pose=True)
    with pytest.raises(FitError, match="robust loss"):
        fit_points(pts, "perspective", SIZE, loss="tukey")
    with pytest.raises(FitError, match="positive"):
        fit_points(pts, "perspective", SIZE, scale=0)
