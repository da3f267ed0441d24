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
from lenslab.lenses.solve import invert_increasing
from tests.test_lenses_roundtrip import CASES


#: models whose image centre is not the forward direction (face borders, two lenses, looking down, off centre)
NOT_CENTRED = ("cubemap", "tiled", "equirect:", "eac", "dual-fisheye", "little-planet", "fisheye:vfov=150")


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


# -- numeric inverses ----------------------------------------------------------------------------
@settings(max_examples=60, deadline=None)
@given(k1=st.floats(-0.5, 1.0), k2=st.floats(-0.3, 0.5))
def test_division_inverse_converges_to_1e10(k1, k2):
    lens = make_lens(f"distortion:k1={k1},k2={k2}", (1000, 1000))
    hi = min(lens.r_fold, lens.r_corner)
    r_d = np.linspace(0, hi, 2001)[:-1]  # up to (not at) the fold or the corner
    r_u, _ = lens.radius_map(r_d)
    solved, valid, converged = lens.invert_radius(r_u)
    assert converged.all() and valid.all()
    back, _ = lens.radius_map(solved)
    # 1e-10, relative once r_u > 1 (next to a pole r_u runs to 1e16 and only its leading digits exist)
    assert (np.abs(back - r_u) <= 1e-10 * np.maximum(1.0, r_u)).all()
    # where the map is well conditioned (slope >= 1e-3) the radius itself is recovered to 1e-10
    _, slope = lens.radius_map(r_d)
    good = slope >= 1e-3
    assert np.abs(solved - r_d)[good].max() <= 1e-10


def test_division_inverse_reports_failures():
    lens = make_lens("pincushion:k1=0.3,k2=0.5", (1000, 1000))
    r_max, _ = lens.radius_map(np.array([lens.r_fold]))
    _, valid, converged = lens.invert_radius(np.array([0.2, r_max[0], 2 * r_max[0], -1.0, np.nan]))
    assert list(valid) == [True, False, False, False, False]
    # a solve cut short is reported, never returned as a result
    target = np.linspace(0.01, 0.5, 50)  # below the largest r_u (0.575, at the fold)
    x, conv = invert_increasing(lens.radius_map, target, 0.0, lens.r_fold, np.zeros(50), max_iter=2)
    assert not conv.all()
    x, conv = invert_increasing(lens.radius_map, target, 0.0, lens.r_fold, np.zeros(50))
    assert conv.all() and np.abs(lens.radius_map(x)[0] - target).max() <= 1e-10


def test_solver_survives_flat_and_wrong_slopes():
    """Bisection takes over where Newton cannot: a cubic with a flat inflection at the root."""
    f = lambda x: ((x - 0.3) ** 3, 3 * (x - 0.3) ** 2)
    target = np.array([0.0, 1e-9, -1e-3, 0.2])
    x, conv = invert_increasing(f, target, -1.0, 1.0, np.full(4, 0.3))
    assert conv.all()
    assert np.allclose(x, 0.3 + np.cbrt(target), atol=1e-12)


@pytest.mark.parametrize("spec", ["pincushion:k1=0.3,k2=0.05", "barrel:k1=-1.0", "distortion:k1=0.2,k2=-0.6",
                                  "brown:k1=0.5,k2=-0.32", "seedfisheye:fov=170"])
def test_compiled_solver_matches_the_vectorised_one(spec):
    """The models solve with a compiled per-element loop; it must agree with invert_increasing."""
    from lenslab.lenses.solve import (BROWN, DIVISION, DIVISION_RECIPROCAL, SEED_PSI, invert_increasing,
                                      solve_radial)

    lens = make_lens(spec, (100, 100))
    rng = np.random.default_rng(7)
    if lens.name == "seedfisheye":
        f, kind, p, hi = lens.psi, SEED_PSI, (lens.F, 0.0), lens.r_max
    elif lens.name == "brown":
        f, kind, p, hi = lens.radius_map, BROWN, (lens.k1, lens.k2), lens.ru_fold
    else:
        f, kind, p, hi = lens.radius_map, DIVISION, (lens.k1, lens.k2), min(lens.r_fold, lens.r_corner)
    x_true = rng.random(3000) * hi
    target, _ = f(x_true)
    x0 = rng.random(3000) * hi
    a, ca = invert_increasing(f, target, 0.0, hi, x0)
    b, cb = solve_radial(kind, p[0], p[1], target, hi, x0)
    assert ca.all() and cb.all()
    if kind == SEED_PSI:
        # tan, sin, cos and atan2 come from different libraries (NumPy's and LLVM's libm), which
        # may differ in the last bit; the roots then agree to the solver's tolerance
        assert np.abs(a - b).max() < 1e-12
    else:
        assert np.array_equal(a, b)  # the same algorithm, the same float operations
    if lens.name in ("barrel", "distortion") and lens.pole:
        far = target > 1
        a, _ = invert_increasing(lens._reciprocal_radius_map, -1 / target[far], 0.0, hi, x0[far])
        b, _ = solve_radial(DIVISION_RECIPROCAL, p[0], p[1], -1 / target[far], hi, x0[far])
        assert np.array_equal(a, b)
