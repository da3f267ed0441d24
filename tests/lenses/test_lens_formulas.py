"""The lens kit's formulas (lenslab.lenses.formulas): published values, and each NumPy function against
its compiled twin (the C++ kernels, ``lenslab.cxx_kernels``), so that the fisheye mappings and the cylinders
agree everywhere."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lenslab.lenses.core.native import lens_kernels
from lenslab.lenses.formulas import azimuthal, calibrated, kinds, lonlat

AZIMUTHAL = list(kinds.AZIMUTHAL.values())
CYLINDERS = [kinds.EQUIRECTANGULAR, kinds.CYLINDRICAL, kinds.EQUAL_AREA_CYLINDRICAL, kinds.MERCATOR]


@pytest.mark.parametrize("kind,theta_deg,radius", [
    # Kannala and Brandt 2006, table 1, at unit focal length; lensfun's Thoby fit (lens.cpp: 1.47 sin(0.713 theta))
    (kinds.EQUIDISTANT, 90.0, math.pi / 2),
    (kinds.EQUISOLID, 90.0, math.sqrt(2.0)),
    (kinds.STEREOGRAPHIC, 90.0, 2.0),
    (kinds.ORTHOGRAPHIC, 30.0, 0.5),
    (kinds.THOBY, 60.0, 1.47 * math.sin(0.713 * math.pi / 3)),
])
def test_azimuthal_radius_at_published_angles(kind, theta_deg, radius):
    theta = math.radians(theta_deg)
    assert float(azimuthal.radius_of_angle(kind, theta)) == pytest.approx(radius, abs=1e-15)
    d, ok = azimuthal.plane_to_dir(kind, np.array([radius]), np.array([0.0]))
    assert ok[0] and d[0] == pytest.approx([math.sin(theta), 0.0, math.cos(theta)], abs=1e-15)


@pytest.mark.parametrize("kind,lat_deg,height", [
    # Snyder 1987: Mercator y(30 deg) = ln tan(60 deg) = 0.5493061443; central cylinder tan; Lambert sin
    (kinds.MERCATOR, 30.0, 0.5493061443340549),
    (kinds.CYLINDRICAL, 45.0, 1.0),
    (kinds.EQUAL_AREA_CYLINDRICAL, 30.0, 0.5),
    (kinds.EQUIRECTANGULAR, 30.0, math.pi / 6),
])
def test_cylinder_heights_at_published_latitudes(kind, lat_deg, height):
    lat = math.radians(lat_deg)
    y, ok = lonlat.lat_to_height(kind, np.array([math.sin(lat)]), np.array([math.cos(lat)]))
    assert ok[0] and y[0] == pytest.approx(height, abs=1e-15)
    s, c, ok = lonlat.height_to_lat(kind, np.array([height]))
    assert ok[0] and math.atan2(s[0], c[0]) == pytest.approx(lat, abs=1e-15)


def random_directions(n=2000, seed=0):
    d = np.random.default_rng(seed).normal(size=(n, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    return np.concatenate([d, np.eye(3), -np.eye(3)])


def plane_points(kind, d):
    """The compiled kernels' plane point of each direction: the lensfun kernel at unit focal length, no
    distortion, centre 0 and one unit per pixel, so its pixel is ``(x, -y)``."""
    out, ok = np.empty((len(d), 2)), np.empty(len(d), dtype=bool)
    lens_kernels().lensfun_dir_to_pixel(d, kind, 1.0, np.ones(1), np.inf, 0.0, 0.0, 1.0, out, ok)
    return out * [1.0, -1.0], ok


@pytest.mark.parametrize("kind", AZIMUTHAL)
def test_azimuthal_twins_agree(kind):
    d = random_directions()
    xy, s, seen = azimuthal.dir_to_plane(kind, d)
    got, ok = plane_points(kind, d)
    back = (d[:, 2] < 0) & (d[:, 0] == 0) & (d[:, 1] == 0)
    assert not ok[back].any()  # the back pole is a circle: the compiled kernel (a pixel per direction) refuses it
    np.testing.assert_array_equal(ok[~back], seen[~back])
    # the same operations in the same order; libm's atan2 and sqrt may differ by an ulp of s
    assert np.all(np.abs(got[ok] - xy[ok]) <= 4e-15 * np.maximum(1.0, s[ok])[:, None])


@pytest.mark.parametrize("kind", CYLINDERS)
def test_cylinder_twins_agree(kind):
    d = random_directions()
    phi, s, c = lonlat.dir_to_lonlat(d)
    y, ok = lonlat.lat_to_height(kind, s, c)
    got, ok2 = plane_points(kind, d)
    np.testing.assert_array_equal(ok2, ok)
    np.testing.assert_allclose(got[ok, 0], phi[ok], rtol=4e-16, atol=1e-300)  # libm atan2s: 1 ulp apart
    np.testing.assert_allclose(got[ok, 1], y[ok], rtol=1e-15, atol=1e-15)


CALIBRATED = [
    (kinds.RECTILINEAR, (0.0, 0.0, 0.0)),
    (kinds.FOV, (0.9, 2.0 * math.tan(0.45), 0.0)),
    (kinds.EQUIDISTANT, (0.0, 0.0, 0.0)),
    (kinds.UNIFIED, (1.6, 1.0 / 1.6, 0.0)),
    (kinds.DOUBLE_SPHERE, (-0.2, 0.6, 0.5)),
    (kinds.EUCM, (0.6, 1.1, 0.4)),
]


@pytest.mark.parametrize("kind,q", CALIBRATED)
def test_calibrated_projection_twins_agree(kind, q):
    """The compiled projection without distortion, ``fx = fy = 1`` and the principal point at (4, 4) of an 8x8
    image, against the NumPy formulas; and its inverse, the compiled unprojection, against theirs."""
    qa = np.array(q)
    d = random_directions(500, seed=1)
    cv = d * [1.0, -1.0, 1.0]  # OpenCV's frame: y down
    mx, my, ok = calibrated.project(kind, cv[:, 0], cv[:, 1], cv[:, 2], qa)
    ok &= (np.abs(mx) <= 4.0) & (np.abs(my) <= 4.0)
    k = lens_kernels()
    z3, z4 = np.zeros(3), np.zeros(4)
    xy, seen = np.empty((len(d), 2)), np.empty(len(d), dtype=bool)
    k.calibrated_project(d, kind, qa, z4, z3, 0.0, 0.0, z4, False, False, np.inf, 1.0, 1.0, 0.0, 3.5, 3.5, 8.0, 8.0,
                         0.0, xy, seen)
    np.testing.assert_array_equal(seen, ok)
    # u = mx + 4: one ulp of 4 (8.9e-16) on top of the formulas' last bits
    np.testing.assert_allclose(xy[ok] - 4.0, np.c_[mx, my][ok], rtol=0, atol=2e-15)
    X, Y, Z, ok_back = calibrated.unproject(kind, mx[ok], my[ok], qa)
    back, ok2 = np.empty((ok.sum(), 3)), np.empty(ok.sum(), dtype=bool)
    k.calibrated_unproject(np.c_[mx, my][ok] + 4.0, kind, qa, z4, z3, 0.0, 0.0, z4, False, False, np.inf, 1.0, 1.0,
                           False, np.zeros(2), 1.0, 1e-13, 1e-11, 1e-15, 100, 1e-12, 10, 1.0, 1.0, 0.0, 3.5, 3.5,
                           back, ok2)
    np.testing.assert_array_equal(ok2, ok_back)
    np.testing.assert_allclose(back[ok2], np.c_[X, -Y, Z][ok2], rtol=0, atol=1e-12)
    np.testing.assert_allclose(back[ok2], d[ok][ok2], rtol=0, atol=1e-9)  # and the inverse is the inverse


def test_lensfun_fisheye_kernel_does_not_put_the_back_pole_at_the_centre():
    # the back pole is the whole rim circle of an equidistant fisheye (s = pi), not one pixel; the lensfun
    # kernel once mapped it to the lens centre as a valid pixel, the calibrated kernel never did
    d = np.array([[0.0, 0.0, -1.0], [0.0, 0.0, 1.0]])
    out, valid = np.empty((2, 2)), np.empty(2, dtype=bool)
    lens_kernels().lensfun_dir_to_pixel(d, kinds.EQUIDISTANT, 1.0, np.ones(1), np.inf, 100.0, 50.0, 0.01, out, valid)
    assert valid.tolist() == [False, True] and out[1].tolist() == [100.0, 50.0]


def test_radial_polynomial_twin_agrees():
    from lenslab.lenses.formulas.radial import Radial

    # lensfun's ptlens a=0.01, b=-0.02, c=0.005 as P(r) = (1 - a - b - c) + c r + b r^2 + a r^3
    radial = Radial((1.005, 0.005, -0.02, 0.01))
    r = np.linspace(0.0, 1.5, 31)
    # the lensfun kernel, rectilinear at unit focal length: the direction (r, 0, 1) is the plane point (r, 0),
    # which it moves to r P(r) (r to an ulp or two: the direction is normalised first)
    out, ok = np.empty((len(r), 2)), np.empty(len(r), dtype=bool)
    lens_kernels().lensfun_dir_to_pixel(np.c_[r, 0 * r, 1 + 0 * r], kinds.RECTILINEAR, 1.0, radial.coeffs, np.inf,
                                        0.0, 0.0, 1.0, out, ok)
    assert ok.all() and out[:, 0] == pytest.approx((r * radial.scale(r)).tolist(), rel=1e-15, abs=1e-300)
    assert radial.scale(np.array([1.0]))[0] == pytest.approx(1.0, abs=1e-15)  # lensfun's P(1) = 1 for ptlens
