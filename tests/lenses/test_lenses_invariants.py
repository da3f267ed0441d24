"""Geometric invariants of the lens models: the centre looks down +z, the fisheye rim is fov/2 from the
axis, equisolid pixels hold equal solid angles, perspective keeps straight lines straight, the cube
faces sit where ffmpeg's v360 puts them, and the numeric inverses converge (or say they did not).
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lenslab.lenses import make_lens
from lenslab.lenses.formulas.solve import invert_increasing
from tests.lenses.test_lenses_roundtrip import CASES


#: models whose image centre is not the forward direction (face borders, two lenses, looking down, off centre)
NOT_CENTRED = ("cubemap", "tiled", "equirect:", "eac", "dual-fisheye", "little-planet", "fisheye:vfov=150",
               "stereo", "fb-barrel", "tetrahedron", "tsp")  # two eyes side by side; faces and parts of a layout


@pytest.mark.parametrize("spec,size", [c for c in CASES if not c[0].startswith(NOT_CENTRED)],
                         ids=[c[0] for c in CASES if not c[0].startswith(NOT_CENTRED)])
def test_centre_pixel_is_plus_z(spec, size):
    lens = make_lens(spec, size)
    d, ok = lens.pixel_to_dir([[size[0] / 2, size[1] / 2]])
    assert ok[0] and np.array_equal(d[0], [0.0, 0.0, 1.0])
    xy, ok = lens.dir_to_pixel([[0.0, 0.0, 1.0]])
    assert ok[0] and np.array_equal(xy[0], [size[0] / 2, size[1] / 2])


@pytest.mark.parametrize("mapping,fovs", [
    ("equidistant", (1.0, 90.0, 180.0, 270.0, 359.0)),
    ("equisolid", (1.0, 90.0, 180.0, 270.0, 359.0)),
    ("stereographic", (1.0, 90.0, 180.0, 270.0, 350.0)),
    ("orthographic", (1.0, 90.0, 150.0, 180.0)),
])
def test_fisheye_rim_is_half_fov_from_axis(mapping, fovs):
    a = np.linspace(0, 2 * np.pi, 361)
    for fov in fovs:
        lens = make_lens(f"fisheye:fov={fov},mapping={mapping}", (2000, 2000))
        xy = np.c_[1000 * (1 + np.cos(a)), 1000 * (1 - np.sin(a))]
        d, ok = lens.pixel_to_dir(xy)
        assert ok.all()
        theta = np.arctan2(np.hypot(d[:, 0], d[:, 1]), d[:, 2])
        # 1e-12 rad: the circle's pixel coordinates carry ~1e-13 px of rounding; the orthographic rim
        # at fov 180 magnifies that (da/dr infinite there) to sqrt(2e-16) ~ 1.5e-8 rad
        tol = 3e-8 if (mapping == "orthographic" and fov == 180) else 1e-12
        assert np.abs(theta - np.radians(fov) / 2).max() < tol
        # and the direction's azimuth is the pixel's (1e-12 rad: rounding of the circle's coordinates)
        dazi = np.angle(np.exp(1j * (np.arctan2(d[:, 1], d[:, 0]) - a)))
        assert np.abs(dazi).max() < 1e-12


def solid_angle_density(lens, xy, h=1e-3):
    """Solid angle per square pixel at ``xy``: |dd/dx x dd/dy| by central differences (d is unit)."""
    dx = (lens.pixel_to_dir(xy + [h, 0])[0] - lens.pixel_to_dir(xy - [h, 0])[0]) / (2 * h)
    dy = (lens.pixel_to_dir(xy + [0, h])[0] - lens.pixel_to_dir(xy - [0, h])[0]) / (2 * h)
    return np.linalg.norm(np.cross(dx, dy), axis=-1)


@pytest.mark.parametrize("fov", [1.0, 90.0, 180.0, 300.0, 360.0])
def test_equisolid_pixels_hold_equal_solid_angle(fov):
    w = 1000
    lens = make_lens(f"fisheye:fov={fov},mapping=equisolid", (w, w))
    rng = np.random.default_rng(3)
    # uniform over the disc, off the rim: the differences must not straddle it, and at fov 360 the rim
    # is the back pole, where the rounding of the differences grows as 1/cos(a/2)
    r = np.sqrt(rng.random(5000)) * 0.99
    a = rng.random(5000) * 2 * np.pi
    xy = np.c_[w / 2 * (1 + r * np.cos(a)), w / 2 * (1 - r * np.sin(a))]
    density = solid_angle_density(lens, xy)
    # the disc of radius w/2 px holds the cap of half-angle F: 4 pi sin^2(F/2) sr over pi (w/2)^2 px^2
    expect = 4 * np.sin(np.radians(fov) / 4) ** 2 / (w / 2) ** 2
    # 1e-7 relative: central differences with h = 1e-3 px have truncation ~h^2/w^2 and rounding
    # ~1e-16 / (h * dd/dx) ~ 1e-11 relative; the pixels themselves are equal to far better than this
    assert np.abs(density / expect - 1).max() < 1e-7
    # the check discriminates: equidistant pixels at the same fov do vary
    other = solid_angle_density(make_lens(f"fisheye:fov={fov},mapping=equidistant", (w, w)), xy)
    assert np.ptp(other) / other.mean() > (1e-5 if fov < 10 else 0.05)


@settings(max_examples=50, deadline=None)
@given(x0=st.floats(0, 1920), y0=st.floats(0, 1080), x1=st.floats(0, 1920), y1=st.floats(0, 1080),
       fov=st.floats(1.0, 170.0))
def test_perspective_keeps_lines_straight(x0, y0, x1, y1, fov):
    """Points on an image line map to directions in one plane through the eye."""
    if np.hypot(x1 - x0, y1 - y0) < 1.0:
        return
    lens = make_lens(f"perspective:fov={fov}", (1920, 1080))
    t = np.linspace(0, 1, 50)[:, None]
    xy = (1 - t) * np.array([x0, y0]) + t * np.array([x1, y1])
    d, ok = lens.pixel_to_dir(xy)
    assert ok.all()
    n = np.cross(d[0], d[-1])
    n /= np.linalg.norm(n)
    # 1e-12: the directions carry ~1e-16 rounding each; the plane's normal from two of them a bit more
    # when they are close (>= 1 px apart: 1e-16 / angle ~ 1e-12 at the narrowest fov)
    assert np.abs(d @ n).max() < 1e-12


def test_cubemap_faces_match_ffmpeg_layout():
    """Face centres of the 3x2 layout rludfb: right, left, up / down, front, back."""
    lens = make_lens("cubemap", (600, 400))
    expect = [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]]
    d, ok = lens.pixel_to_dir(np.array([[100, 100], [300, 100], [500, 100], [100, 300], [300, 300], [500, 300]],
                                       dtype=float))
    assert ok.all() and np.allclose(d, expect, atol=1e-15)

    # orientation: image-up is +y on the side faces; the up face's bottom edge and the down face's top
    # edge meet the front face; moving right on the right face turns toward the back (-z)
    def at(x, y):
        return lens.pixel_to_dir([[x, y]])[0][0]

    assert at(300, 210)[2] > 0.5 and at(300, 210)[1] > 0.5  # front face near its top edge: up and forward
    assert at(500, 199)[2] > 0.5 and at(500, 199)[1] > 0.5  # up face near its bottom edge: toward front
    assert at(100, 210)[2] > 0.5 and at(100, 210)[1] < -0.5  # down face near its top edge: toward front
    assert at(190, 100)[2] < -0.5 and at(10, 100)[2] > 0.5  # right face: left edge front, right edge back
    assert at(210, 100)[2] < -0.5 and at(390, 100)[2] > 0.5  # left face: left edge back, right edge front
    assert at(410, 300)[0] > 0.5 and at(590, 300)[0] < -0.5  # back face: left edge +x, right edge -x
    # the 6x1 layout has the same faces in a row
    row = make_lens("cubemap:layout=6x1", (1200, 200))
    d6, _ = row.pixel_to_dir(np.c_[np.arange(100, 1200, 200), np.full(6, 100.0)])
    assert np.allclose(d6, expect, atol=1e-15)


# -- numeric inverses, through the calls production makes ---------------------------------------
W = 1000  # a square image: u = 2x/W - 1, v = 1 - 2y/W; the diagonal reaches the corner at r = sqrt(2)


def diagonal_pixels(r: np.ndarray) -> np.ndarray:
    """Pixels at normalised radius ``r`` on the upper-right diagonal (u = v = r / sqrt 2)."""
    c = r / np.sqrt(2.0)
    return np.stack([(c + 1.0) * W / 2, (1.0 - c) * W / 2], axis=-1)


def perspective_ray(r_u: np.ndarray) -> np.ndarray:
    """The ray of undistorted radius ``r_u`` on that diagonal through a 90-degree perspective base
    (d ~ (u tan 45, v tan 45, 1), docs/conventions.md)."""
    c = r_u / np.sqrt(2.0)
    return np.stack([c, c, np.ones_like(c)], axis=-1)


@settings(max_examples=60, deadline=None)
@given(k1=st.floats(-0.5, 1.0), k2=st.floats(-0.3, 0.5))
def test_division_model_dir_to_pixel_solves_to_1e10(k1, k2):
    # dir -> pixel solves r_u = r_d / (1 + k1 r_d^2 + k2 r_d^4) for r_d: the formula is written out here
    lens = make_lens(f"distortion:k1={k1},k2={k2},fov=90", (W, W))
    hi = min(lens.r_fold, lens.r_corner / (1.0 + 1e-9))
    r_d = np.linspace(0, hi, 2001)[:-1]  # up to (not at) the fold or the corner
    den = 1.0 + k1 * r_d**2 + k2 * r_d**4
    r_u = r_d / den
    ok = (den > 0) & (r_u < 1e6)  # beyond a pole the ray would look backwards
    xy, valid = lens.dir_to_pixel(perspective_ray(r_u[ok]))
    assert valid.all()
    # where the map is well conditioned (dr_u/dr_d >= 1e-3) the radius is recovered to 1e-10
    slope = (1.0 - k1 * r_d**2 - 3 * k2 * r_d**4) / den**2
    good = slope[ok] >= 1e-3
    err = np.abs(xy - diagonal_pixels(r_d[ok])).max(axis=-1) / (W / 2)  # in units of r
    assert err[good].max() <= 1e-10


def test_division_model_refuses_rays_past_the_fold():
    lens = make_lens("pincushion:k1=0.3,k2=0.5,fov=90", (W, W))
    r_fold = lens.r_fold
    r_u_max = r_fold / (1 + 0.3 * r_fold**2 + 0.5 * r_fold**4)  # the largest r_u the lens shows
    rays = perspective_ray(np.array([0.2, r_u_max * 1.001, 2 * r_u_max]))
    rays = np.vstack([rays, [0.0, 0.0, -1.0], [np.nan, 0.0, 1.0]])
    xy, valid = lens.dir_to_pixel(rays)
    assert list(valid) == [True, False, False, False, False]
    assert np.all(xy[~valid] == 0.0)
    u, v = xy[0, 0] / (W / 2) - 1, 1 - xy[0, 1] / (W / 2)
    r = np.hypot(u, v)  # the valid one: r_u = 0.2 on the diagonal, solved for r_d
    assert abs(r / (1 + 0.3 * r**2 + 0.5 * r**4) - 0.2) <= 1e-12 and abs(u - v) <= 1e-12


@settings(max_examples=40, deadline=None)
@given(k1=st.floats(-0.4, 0.6), k2=st.floats(-0.2, 0.3))
def test_brown_pixel_to_dir_solves_to_1e10(k1, k2):
    # pixel -> dir solves r_d = r_u (1 + k1 r_u^2 + k2 r_u^4) for r_u: the formula is written out here
    lens = make_lens(f"brown:k1={k1},k2={k2},fov=90", (W, W))
    r_u = np.linspace(0, min(lens.ru_fold, 3.0), 2001)[:-1]
    r_d = r_u * (1 + k1 * r_u**2 + k2 * r_u**4)
    inside = r_d <= np.sqrt(2.0) * (1 - 1e-9)  # pixels inside the image
    d, valid = lens.pixel_to_dir(diagonal_pixels(r_d[inside]))
    assert valid.all()
    r_u_back = np.hypot(d[:, 0], d[:, 1]) / d[:, 2]  # tan 45 = 1: the undistorted radius of the ray
    slope = 1 + 3 * k1 * r_u**2 + 5 * k2 * r_u**4
    good = slope[inside] >= 1e-3
    assert np.abs(r_u_back - r_u[inside])[good].max() <= 1e-10 * max(1.0, r_u.max())


def test_bisection_guards_newton():
    """The bracketed Newton of lenslab.lenses.formulas.solve (used by the radial models): cut short it reports
    failure, never a result; run out it reaches 1e-10."""
    f = lambda x: (x * (1 + 0.3 * x * x), 1 + 0.9 * x * x)
    target = np.linspace(0.01, 0.5, 50)
    x, conv = invert_increasing(f, target, 0.0, 1.0, np.zeros(50), max_iter=2)
    assert not conv.all()
    x, conv = invert_increasing(f, target, 0.0, 1.0, np.zeros(50))
    assert conv.all() and np.abs(x * (1 + 0.3 * x * x) - target).max() <= 1e-10


def test_solver_survives_flat_and_wrong_slopes():
    """Bisection takes over where Newton cannot: a cubic with a flat inflection at the root."""
    f = lambda x: ((x - 0.3) ** 3, 3 * (x - 0.3) ** 2)
    target = np.array([0.0, 1e-9, -1e-3, 0.2])
    x, conv = invert_increasing(f, target, -1.0, 1.0, np.full(4, 0.3))
    assert conv.all()
    assert np.allclose(x, 0.3 + np.cbrt(target), atol=1e-12)


