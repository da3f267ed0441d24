"""The lens kit's formulas (lenslab.lenses.formulas): published values, and each NumPy function against
its compiled twin, so that the fisheye mappings and the cylinders are written once and agree everywhere."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lenslab.lenses.formulas import azimuthal, azimuthal_kernels, kinds, lonlat, lonlat_kernels

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


@pytest.mark.parametrize("kind", AZIMUTHAL)
def test_azimuthal_twins_agree(kind):
    d = random_directions()
    xy, s, seen = azimuthal.dir_to_plane(kind, d)
    for i, (dx, dy, dz) in enumerate(d):
        x, y, ok = azimuthal_kernels.dir_to_plane(kind, dx, dy, dz)
        back = dz < 0 and dx == 0 and dy == 0
        if back:  # the back pole is a circle: the compiled kernel (a pixel per direction) refuses it
            assert not ok
            continue
        assert ok == bool(seen[i]), (kind, d[i])
        if ok:
            assert abs(x - xy[i, 0]) <= 1e-15 * max(1.0, s[i]) * 4 and abs(y - xy[i, 1]) <= 1e-15 * max(1.0, s[i]) * 4
            e, f, g, ok2 = azimuthal_kernels.plane_to_dir(kind, x, y)
            ref, ok3 = azimuthal.plane_to_dir(kind, np.array([x]), np.array([y]))
            assert ok2 == bool(ok3[0]) and np.allclose([e, f, g], ref[0], rtol=0, atol=1e-15)


@pytest.mark.parametrize("kind", CYLINDERS)
def test_cylinder_twins_agree(kind):
    d = random_directions()
    phi, s, c = lonlat.dir_to_lonlat(d)
    y, ok = lonlat.lat_to_height(kind, s, c)
    for i, (dx, dy, dz) in enumerate(d):
        p, h, ok2 = lonlat_kernels.dir_to_lon_height(kind, dx, dy, dz)
        assert ok2 == bool(ok[i]) and p == pytest.approx(phi[i], rel=4e-16, abs=1e-300)  # libm atan2s: 1 ulp apart
        if ok2:
            assert h == pytest.approx(y[i], rel=1e-15, abs=1e-15)


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
    from lenslab.lenses.formulas import calibrated, calibrated_kernels

    qa = np.array(q)
    d = random_directions(500, seed=1)
    mx, my, ok = calibrated.project(kind, d[:, 0], d[:, 1], d[:, 2], qa)
    X, Y, Z, ok_back = calibrated.unproject(kind, mx, my, qa)
    for i in range(d.shape[0]):
        a, b, seen = calibrated_kernels.project_one(kind, d[i, 0], d[i, 1], d[i, 2], qa)
        assert seen == bool(ok[i]), (kind, d[i])
        if seen:
            assert abs(a - mx[i]) <= 1e-12 * max(1.0, abs(a)) and abs(b - my[i]) <= 1e-12 * max(1.0, abs(b))
            e, f, g, ok2 = calibrated_kernels.unproject_one(kind, a, b, qa)
            assert ok2 == bool(ok_back[i]) and np.allclose([e, f, g], [X[i], Y[i], Z[i]], rtol=0, atol=1e-12)
            if ok2:  # and the inverse is the inverse
                assert np.allclose([e, f, g], d[i], rtol=0, atol=1e-9)


def test_lensfun_fisheye_kernel_does_not_put_the_back_pole_at_the_centre():
    # the back pole is the whole rim circle of an equidistant fisheye (s = pi), not one pixel; the lensfun
    # kernel once mapped it to the lens centre as a valid pixel, the calibrated kernel never did
    from lenslab.lenses.lensfun.kernels import dir_to_pixel

    d = np.array([[0.0, 0.0, -1.0], [0.0, 0.0, 1.0]])
    out, valid = np.empty((2, 2)), np.empty(2, dtype=bool)
    dir_to_pixel(d, kinds.EQUIDISTANT, 1.0, np.ones(1), np.inf, 100.0, 50.0, 0.01, out, valid)
    assert valid.tolist() == [False, True] and out[1].tolist() == [100.0, 50.0]


def test_radial_polynomial_twin_agrees():
    from lenslab.lenses.formulas.radial import Radial
    from lenslab.lenses.formulas.radial_kernels import poly_scale

    # lensfun's ptlens a=0.01, b=-0.02, c=0.005 as P(r) = (1 - a - b - c) + c r + b r^2 + a r^3
    radial = Radial((1.005, 0.005, -0.02, 0.01))
    r = np.linspace(0.0, 1.5, 31)
    assert [poly_scale(radial.coeffs, x) for x in r] == pytest.approx(radial.scale(r).tolist(), rel=1e-15)
    assert poly_scale(radial.coeffs, 1.0) == pytest.approx(1.0, abs=1e-15)  # lensfun's P(1) = 1 for ptlens
