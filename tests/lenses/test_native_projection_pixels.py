"""The compiled direction -> pixel of the fisheye mappings, the little planet, two fisheyes back to back, the cylinders
(central, Lambert's equal-area, Mercator), the sinusoidal map, Pannini and the Brown-distorted and swirled pinholes
(``src/native/lens_pixels.cpp``).

Each kernel is held to the model's own NumPy steps (``Lens.dir_to_pixel`` with the kernel switched off: they are its
specification) by ``test_native_lens_kernels.py`` (hypothesis directions with the poles, the seam, the axis, the
back pole, zero, NaN and infinite ones mixed in, fields of view near 0 and 360 degrees, a distortion's fold); here,
to the published formula, transcribed here in float64 with trigonometry where the kernel has none
(stereographic ``r = 2 f tan(theta/2)`` where the kernel takes ``2 rho / (1 + dz)``, Mercator's
``ln tan(pi/4 + phi/2)`` where it takes ``asinh(dy / hypot(dx, dz))``), or OpenCV's ``projectPoints``.

Tolerance: the published formulas reach the same pixel through other roundings (a tangent of a half angle, a
logarithm, glibc's vector arc tangents within 4 ulps in the kernel): a few ulps of a radius of at most 2048 px, about
1e-12 px, so 1e-9 px (the kernels' tolerance against their NumPy steps) holds with 1e3 to spare.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given

from lenslab.lenses import make_lens
from lenslab.lenses.core.native import project_kernel
from tests.lenses.test_native_lens_kernels import DIRS, HYP, numpy_steps
from tests.lenses.test_native_pixel_dirs import fisheyes

TOL = 1e-9  # px (see the module's docstring)

def test_the_kernels_run_where_the_models_are_subclassed_unchanged_only():
    """A subclass that changes a step of dir_to_pixel has no kernel (its own NumPy steps run)."""
    from lenslab.lenses.projections.cylindrical import Mercator
    from lenslab.lenses.projections.fisheye import Fisheye

    class Shifted(Mercator):
        def lat_to_v(self, s, c):
            v, ok = super().lat_to_v(s, c)
            return v + 0.1, ok

    class Moved(Fisheye):
        def _from_local(self, uv):
            return uv + 0.1

    assert Shifted(64, 64).pixel_kernel() is None and Moved(64, 64).pixel_kernel() is None
    assert make_lens("brown:k1=0.1,base=fisheye", (64, 64)).pixel_kernel() is None  # a pinhole's only


def _unit(rng, n):
    d = rng.normal(size=(n, 3))
    return d / np.linalg.norm(d, axis=1, keepdims=True)


#: Kannala and Brandt (2006), table 1: image radius of the angle theta from the axis, focal length f
FISHEYE_R = {
    "equidistant": lambda f, t: f * t,
    "equisolid": lambda f, t: 2.0 * f * np.sin(t / 2.0),
    "stereographic": lambda f, t: 2.0 * f * np.tan(t / 2.0),
    "orthographic": lambda f, t: f * np.sin(t),
}


def _fisheye_pixels(lx, ly, lz, mapping, fov, w, h):
    """A fisheye of ``fov`` across the width ``w`` at the angle theta = atan2(hypot(lx, ly), lz) from its axis and
    azimuth atan2(ly, lx): r = g(f, theta) with g(f, fov/2) = w/2, x = w/2 + r cos(azimuth), y = h/2 - r sin."""
    g = FISHEYE_R[mapping]
    half = np.radians(fov) / 2.0
    f = (w / 2.0) / g(1.0, half)
    theta = np.arctan2(np.hypot(lx, ly), lz)
    az = np.arctan2(ly, lx)
    r = g(f, theta)
    return np.stack([w / 2.0 + r * np.cos(az), h / 2.0 - r * np.sin(az)], -1), theta <= half


@pytest.mark.parametrize("mapping,fov,size", [("stereographic", 180.0, (1024, 1024)),
                                              ("stereographic", 270.0, (2048, 1536)),
                                              ("equidistant", 220.0, (1024, 1024)), ("equisolid", 180.0, (800, 600)),
                                              ("orthographic", 160.0, (1024, 1024))])
def test_fisheye_kernel_is_kannala_brandts_table(mapping, fov, size):
    w, h = size
    d = _unit(np.random.default_rng(7), 20000)
    want, inside = _fisheye_pixels(d[:, 0], d[:, 1], d[:, 2], mapping, fov, w, h)
    in_frame = (want[:, 0] > 1e-6) & (want[:, 0] < w - 1e-6) & (want[:, 1] > 1e-6) & (want[:, 1] < h - 1e-6)
    lens = make_lens(f"fisheye:fov={fov:g},mapping={mapping}", size)
    xy, ok = project_kernel(lens.pixel_kernel(), d)
    seen = inside & in_frame
    assert seen.sum() > 5000
    assert ok[seen].all() and not ok[~inside].any()
    np.testing.assert_allclose(xy[seen], want[seen], rtol=0, atol=TOL)


def test_little_planet_kernel_is_a_stereographic_fisheye_looking_down():
    """The lens's axis is -y, its x axis +x and its y axis +z (forward at the top): (lx, ly, lz) = (dx, dz, -dy)."""
    w = h = 1024
    d = _unit(np.random.default_rng(8), 20000)
    want, inside = _fisheye_pixels(d[:, 0], d[:, 2], -d[:, 1], "stereographic", 270.0, w, h)
    in_frame = (want[:, 0] > 1e-6) & (want[:, 0] < w - 1e-6) & (want[:, 1] > 1e-6) & (want[:, 1] < h - 1e-6)
    xy, ok = project_kernel(make_lens("little-planet", (w, h)).pixel_kernel(), d)
    seen = inside & in_frame
    assert seen.sum() > 5000 and ok[seen].all()
    np.testing.assert_allclose(xy[seen], want[seen], rtol=0, atol=TOL)
    # the nadir at the centre, the horizon straight ahead at r = tan(45) / tan(67.5) of the half width, upward
    xy, ok = project_kernel(make_lens("little-planet", (w, h)).pixel_kernel(), np.array([[0.0, -1.0, 0.0],
                                                                                           [0.0, 0.0, 1.0]]))
    assert ok.all()
    np.testing.assert_allclose(xy, [[512.0, 512.0], [512.0, 512.0 - 512.0 * np.tan(np.pi / 4) /
                                                      np.tan(3 * np.pi / 8)]], rtol=0, atol=TOL)


@pytest.mark.parametrize("mapping,front", [("equidistant", "left"), ("equisolid", "right")])
def test_dual_fisheye_kernel_is_two_fisheyes_back_to_back(mapping, front):
    """ffmpeg v360's dfisheye layout: each half of width W/2 one fisheye of fov 190 across it; the nearer lens sees a
    direction (the back one for dz < 0, whose frame is the camera's turned half a turn about +y: (-dx, dy, -dz))."""
    w, h = 2048, 1024
    half = w / 2.0
    d = _unit(np.random.default_rng(13), 20000)
    back = d[:, 2] < 0
    lx, lz = np.where(back, -d[:, 0], d[:, 0]), np.where(back, -d[:, 2], d[:, 2])
    want, _ = _fisheye_pixels(lx, d[:, 1], lz, mapping, 190.0, half, h)
    x0 = np.where(back, half, 0.0) if front == "left" else np.where(back, 0.0, half)
    want[:, 0] += x0
    lens = make_lens(f"dual-fisheye:fov=190,mapping={mapping},front={front}", (w, h))
    xy, ok = project_kernel(lens.pixel_kernel(), d)
    assert ok.all()
    np.testing.assert_allclose(xy, want, rtol=0, atol=TOL)


#: J. P. Snyder, Map Projections - A Working Manual (1987): the height of the latitude phi on the unit sphere
SNYDER_Y = {
    "mercator": lambda phi: np.log(np.tan(np.pi / 4.0 + phi / 2.0)),  # eq. (7-2)
    "cylindrical-equal-area": np.sin,  # eq. (10-2), standard parallel 0
    "cylindrical": np.tan,  # the central cylinder: rays through its axis
}


@pytest.mark.parametrize("name,extra,size", [("mercator", "", (1024, 1024)), ("mercator", ":fov=200,vfov=150",
                                                                               (1024, 512)),
                                             ("cylindrical-equal-area", "", (1024, 326)),
                                             ("cylindrical-equal-area", ":fov=300,vfov=180", (1024, 512)),
                                             ("cylindrical", ":fov=180,vfov=120", (1024, 512))])
def test_cylinder_kernels_are_snyders_formulas(name, extra, size):
    """x = R (lambda - lambda0) (eq. 7-1, 10-1) and y = R h(phi) about the image centre, with R = W / fov (radians)
    across; with vfov the height spans h(vfov/2) over H/2."""
    w, h = size
    lens = make_lens(name + extra, size)
    fov = np.radians(lens.fov)
    d = _unit(np.random.default_rng(9), 20000)
    lam = np.arctan2(d[:, 0], d[:, 2])
    phi = np.arctan2(d[:, 1], np.hypot(d[:, 0], d[:, 2]))
    phi_ok = np.abs(phi) < np.radians(85.0)  # Mercator's ln tan loses digits at the poles
    R = w / fov
    hgt = SNYDER_Y[name]
    scale_y = R if lens.vfov == 0 else (h / 2.0) / hgt(np.radians(lens.vfov) / 2.0)
    want = np.stack([w / 2.0 + R * lam, h / 2.0 - scale_y * hgt(np.where(phi_ok, phi, 0.0))], -1)
    in_frame = (want[:, 0] > 1e-6) & (want[:, 0] < w - 1e-6) & (want[:, 1] > 1e-6) & (want[:, 1] < h - 1e-6)
    xy, ok = project_kernel(lens.pixel_kernel(), d)
    seen = phi_ok & in_frame
    assert seen.sum() > 3000 and ok[seen].all()
    assert not ok[np.abs(lam) > fov / 2 + 1e-9].any()
    np.testing.assert_allclose(xy[seen], want[seen], rtol=0, atol=TOL)


def test_sinusoidal_kernel_is_snyders_formula():
    """Snyder (1987), section 30, eq. (30-1) and (30-2): x = R (lambda - lambda0) cos(phi), y = R phi, with
    R = W / (2 pi) on a 2:1 frame, the latitude phi = asin(dy) (kept below 85 degrees, where asin keeps its digits)."""
    w, h = 2048, 1024
    d = _unit(np.random.default_rng(14), 20000)
    phi = np.arcsin(d[:, 1])
    lam = np.arctan2(d[:, 0], d[:, 2])
    R = w / (2.0 * np.pi)
    want = np.stack([w / 2.0 + R * lam * np.cos(phi), h / 2.0 - R * phi], -1)
    xy, ok = project_kernel(make_lens("sinusoidal", (w, h)).pixel_kernel(), d)
    keep = np.abs(phi) < np.radians(85.0)
    assert ok.all()
    np.testing.assert_allclose(xy[keep], want[keep], rtol=0, atol=TOL)


@pytest.mark.parametrize("fov,dist,size", [(150.0, 1.0, (1200, 600)), (170.0, 2.0, (1024, 1024)),
                                           (100.0, 0.0, (640, 480))])
def test_pannini_kernel_is_sharpless_formula(fov, dist, size):
    """Sharpless, Postle and German (2010), eq. 1-2: S = (d + 1) / (d + cos phi), x = S sin phi, y = S tan theta,
    scaled so that the edge longitude fov/2 is at the left and right edges: pixel x = W/2 (1 + x / x_F), y = H/2 - W/2
    y / x_F with x_F = S(fov/2) sin(fov/2) (no vertical compression)."""
    w, h = size
    d = _unit(np.random.default_rng(15), 20000)
    phi = np.arctan2(d[:, 0], d[:, 2])
    theta = np.arctan2(d[:, 1], np.hypot(d[:, 0], d[:, 2]))
    S = (dist + 1.0) / (dist + np.cos(phi))
    F = np.radians(fov) / 2.0
    x_f = (dist + 1.0) / (dist + np.cos(F)) * np.sin(F)
    want = np.stack([w / 2.0 * (1.0 + S * np.sin(phi) / x_f), h / 2.0 - w / 2.0 * S * np.tan(theta) / x_f], -1)
    in_frame = ((np.abs(phi) < F) & (want[:, 0] > 1e-6) & (want[:, 0] < w - 1e-6) & (want[:, 1] > 1e-6)
                & (want[:, 1] < h - 1e-6))
    xy, ok = project_kernel(make_lens(f"pannini:fov={fov:g},d={dist:g}", size).pixel_kernel(), d)
    assert in_frame.sum() > 2000 and ok[in_frame].all()
    np.testing.assert_allclose(xy[in_frame], want[in_frame], rtol=0, atol=TOL)


@pytest.mark.parametrize("amount,fov,size", [(6.0, 90.0, (800, 400)), (-3.0, 150.0, (512, 512))])
def test_swirl_kernel_is_the_polar_swirl_of_a_pinhole(amount, fov, size):
    """docs/conventions.md: in polar coordinates (rho, alpha) of the pinhole's (u', v') = (dx / dz, dy / dz) / t, the
    image point is at alpha = alpha' - rho amount, rho kept; pixel x = W/2 (1 + u), y = H/2 - W/2 v."""
    w, h = size
    d = _unit(np.random.default_rng(17), 20000)
    d = d[d[:, 2] > 0.2]
    t = np.tan(np.radians(fov) / 2.0)
    up, vp = d[:, 0] / d[:, 2] / t, d[:, 1] / d[:, 2] / t
    rho, alpha = np.hypot(up, vp), np.arctan2(vp, up) - np.hypot(up, vp) * amount
    want = np.stack([w / 2.0 * (1.0 + rho * np.cos(alpha)), h / 2.0 - w / 2.0 * rho * np.sin(alpha)], -1)
    in_frame = (want[:, 0] > 1e-6) & (want[:, 0] < w - 1e-6) & (want[:, 1] > 1e-6) & (want[:, 1] < h - 1e-6)
    xy, ok = project_kernel(make_lens(f"swirl:amount={amount:g},fov={fov:g}", size).pixel_kernel(), d)
    assert in_frame.sum() > 1000 and ok[in_frame].all()
    np.testing.assert_allclose(xy[in_frame], want[in_frame], rtol=0, atol=TOL)


def test_brown_kernel_is_opencvs_projection():
    """cv2.projectPoints of the same pinhole with OpenCV's radial k1, k2 (in its units: r in focal lengths, so
    k1 / t^2 and k2 / t^4 for lenslab's half widths with t = tan(fov/2)), f = (W/2) / t, the centre at
    (W/2 - 1/2, H/2 - 1/2) (OpenCV's pixel centres are whole numbers, lenslab's half-integers), y down."""
    cv2 = pytest.importorskip("cv2")
    w, h, k1, k2, fov = 640, 480, -0.08, 0.01, 70.0
    t = np.tan(np.radians(fov) / 2.0)
    d = _unit(np.random.default_rng(10), 20000)
    d = d[d[:, 2] > 0.2]
    f = (w / 2.0) / t
    K = np.array([[f, 0.0, w / 2.0 - 0.5], [0.0, f, h / 2.0 - 0.5], [0.0, 0.0, 1.0]])
    pts = np.stack([d[:, 0], -d[:, 1], d[:, 2]], -1)
    cv_xy, _ = cv2.projectPoints(pts.reshape(-1, 1, 3), np.zeros(3), np.zeros(3), K,
                                 np.array([k1 / t**2, k2 / t**4, 0.0, 0.0, 0.0]))
    want = cv_xy.reshape(-1, 2) + 0.5
    in_frame = (want[:, 0] > 1e-6) & (want[:, 0] < w - 1e-6) & (want[:, 1] > 1e-6) & (want[:, 1] < h - 1e-6)
    lens = make_lens(f"brown:k1={k1},k2={k2},fov={fov}", (w, h))
    xy, ok = project_kernel(lens.pixel_kernel(), d)
    assert in_frame.sum() > 1000 and ok[in_frame].all()
    np.testing.assert_allclose(xy[in_frame], want[in_frame], rtol=0, atol=TOL)


@HYP
@given(lens=fisheyes(), d=DIRS)
def test_fisheye_kernel_is_the_models_numpy_steps_for_any_fisheye(lens, d):
    """Any mapping, fov from 1e-6 degrees to its limit, vfov, dfov and off-centre circles, sizes 1 to 4096 px."""
    xy, ok = project_kernel(lens.pixel_kernel(), d)
    want, want_ok = numpy_steps(lens).dir_to_pixel(d)
    np.testing.assert_array_equal(ok, want_ok)
    np.testing.assert_allclose(xy, want, rtol=0, atol=TOL)
