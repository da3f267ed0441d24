"""Fisheye mappings against their formulas: each mapping of docs/conventions.md at several radii (the
formula transcribed here in float64), what each mapping *is* (equidistant: angle linear in r;
equisolid: equal area; stereographic: conformal; orthographic: sin of the angle linear in r), and the
full-frame and off-centre forms (vfov, dfov, cx, cy). Swapping any mapping for another fails these."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lenslab.lenses import make_lens

W = 2000

#: the conventions' a = g(r), F = fov/2, transcribed independently of lenslab/lenses/projections/fisheye.py
FORMULAS = {
    "equidistant": lambda r, F: r * F,
    "equisolid": lambda r, F: 2 * math.asin(r * math.sin(F / 2)),
    "stereographic": lambda r, F: 2 * math.atan(r * math.tan(F / 2)),
    "orthographic": lambda r, F: math.asin(r * math.sin(F)),
}
FOVS = {"equidistant": (90.0, 180.0, 250.0), "equisolid": (120.0, 180.0, 300.0),
        "stereographic": (100.0, 180.0, 270.0), "orthographic": (60.0, 120.0, 180.0)}
RADII = (0.0, 0.1, 0.37, 0.5, 0.8, 0.999, 1.0)


def pixel_at(r: float, psi: float, w: int = W, h: int = W) -> np.ndarray:
    """The pixel at normalised radius r and azimuth psi (counter-clockwise from +x) about the centre."""
    return np.array([w / 2 * (1 + r * math.cos(psi)), h / 2 - w / 2 * r * math.sin(psi)])


@pytest.mark.parametrize("mapping", list(FORMULAS))
def test_each_mapping_at_several_radii(mapping):
    for fov in FOVS[mapping]:
        lens = make_lens(f"fisheye:fov={fov},mapping={mapping}", (W, W))
        F = math.radians(fov) / 2
        for r in RADII:
            for psi in (0.3, 2.0, 4.4):
                a = FORMULAS[mapping](r, F)
                want = np.array([math.sin(a) * math.cos(psi), math.sin(a) * math.sin(psi), math.cos(a)])
                d, ok = lens.pixel_to_dir(pixel_at(r, psi)[None])
                assert ok[0]
                # 1e-12 rad: the pixel's coordinates round at ~1e-13 of the radius; orthographic at fov 180
                # has da/dr infinite at the rim, which magnifies that to sqrt(2e-16) = 1.5e-8
                tol = 3e-8 if (mapping == "orthographic" and fov == 180 and r > 0.99) else 1e-12
                assert np.linalg.norm(d[0] - want) < tol, (fov, r, psi)
                xy, ok = lens.dir_to_pixel(want[None])
                # the inverse: 1e-9 px at 2000 px (the same rounding, seen in pixels; the rim of the
                # orthographic fov 180 comes back from the 1.5e-8 rad above, sqrt(1 - cos) ~ 1e-8 of the radius)
                assert ok[0] and np.abs(xy[0] - pixel_at(r, psi)).max() < (2e-5 if tol > 1e-12 else 1e-9)


def angle_from_axis(lens, r, psi=0.7):
    d, ok = lens.pixel_to_dir(pixel_at(r, psi)[None])
    assert ok[0]
    return math.atan2(math.hypot(d[0, 0], d[0, 1]), d[0, 2])


@settings(max_examples=40, deadline=None)
@given(fov=st.floats(10.0, 350.0), r=st.floats(0.01, 1.0))
def test_equidistant_angle_is_linear_in_r(fov, r):
    lens = make_lens(f"fisheye:fov={fov}", (W, W))
    # a(r) / r is the same everywhere: F
    assert angle_from_axis(lens, r) / r == pytest.approx(math.radians(fov) / 2, rel=1e-11)


@settings(max_examples=40, deadline=None)
@given(fov=st.floats(10.0, 180.0), r=st.floats(0.01, 1.0))
def test_orthographic_sine_of_angle_is_linear_in_r(fov, r):
    lens = make_lens(f"fisheye:fov={fov},mapping=orthographic", (W, W))
    # sin(a(r)) / r is the same everywhere: sin F (1e-9: the rim at fov 180 magnifies rounding, see above)
    assert math.sin(angle_from_axis(lens, r)) / r == pytest.approx(math.sin(math.radians(fov) / 2), rel=1e-9)


def jacobian(lens, xy, h=1e-3):
    """d(direction)/dx and d(direction)/dy by central differences."""
    dx = (lens.pixel_to_dir(xy + [h, 0])[0] - lens.pixel_to_dir(xy - [h, 0])[0]) / (2 * h)
    dy = (lens.pixel_to_dir(xy + [0, h])[0] - lens.pixel_to_dir(xy - [0, h])[0]) / (2 * h)
    return dx, dy


@settings(max_examples=40, deadline=None)
@given(fov=st.floats(10.0, 330.0), r=st.floats(0.02, 0.98), psi=st.floats(0.0, 6.28))
def test_stereographic_is_conformal(fov, r, psi):
    """The image of a small square is a square on the sphere: the Jacobian's columns are orthogonal
    and equally long (checked to 1e-6: central differences with h = 1e-3 px)."""
    lens = make_lens(f"fisheye:fov={fov},mapping=stereographic", (W, W))
    dx, dy = jacobian(lens, pixel_at(r, psi)[None])
    lx, ly = np.linalg.norm(dx), np.linalg.norm(dy)
    assert abs(lx / ly - 1) < 1e-6 and abs(np.dot(dx[0], dy[0])) / (lx * ly) < 1e-6


@settings(max_examples=40, deadline=None)
@given(fov=st.floats(20.0, 300.0), r=st.floats(0.05, 0.95), psi=st.floats(0.0, 6.28))
def test_equisolid_holds_equal_solid_angle_and_the_others_do_not(fov, r, psi):
    """Equal areas of the image hold equal solid angles: |dd/dx x dd/dy| is the same at r and at the
    centre; the equidistant and stereographic mappings at the same fov are not equal-area."""
    def density(mapping, rr):
        lens = make_lens(f"fisheye:fov={fov},mapping={mapping}", (W, W))
        dx, dy = jacobian(lens, pixel_at(rr, psi)[None])
        return np.linalg.norm(np.cross(dx, dy))

    assert density("equisolid", r) / density("equisolid", 0.01) == pytest.approx(1.0, abs=1e-6)
    if r > 0.3:  # away from the centre the others differ by far more than that
        assert abs(density("stereographic", r) / density("stereographic", 0.01) - 1) > 1e-3
        assert abs(density("equidistant", r) / density("equidistant", 0.01) - 1) > 1e-4


# -- full frame and off centre ------------------------------------------------------------------
def test_dfov_puts_the_half_angle_at_the_corner_of_a_3_2_frame():
    w, h = 3000, 2000
    lens = make_lens("fisheye:dfov=180", (w, h))
    for corner in ([0, 0], [w, 0], [0, h], [w, h]):
        d, ok = lens.pixel_to_dir(np.array([corner], dtype=float))
        assert ok[0] and abs(d[0, 2]) < 1e-15  # 90 degrees from the axis
    # the edge centres: equidistant, so the angle is 90 degrees times the radius over the half diagonal
    diag = math.hypot(1.0, h / w)
    for xy, r in (([w, h / 2], 1.0), ([w / 2, 0], h / w)):
        assert angle_from_pixel(lens, xy) == pytest.approx(math.pi / 2 * r / diag, abs=1e-12)
    # a full frame: every pixel has a ray (masked only where the mapping ends, here past the corners)
    yy, xx = np.mgrid[0:h:97, 0:w:97] + 0.5
    assert lens.pixel_to_dir(np.stack([xx, yy], -1))[1].all()


def angle_from_pixel(lens, xy):
    d, ok = lens.pixel_to_dir(np.array([xy], dtype=float))
    assert ok[0]
    return math.atan2(math.hypot(d[0, 0], d[0, 1]), d[0, 2])


def test_vfov_and_circle_offset():
    w, h = 3000, 2000
    lens = make_lens("fisheye:vfov=150,mapping=equisolid,cx=0.1,cy=-0.05", (w, h))
    centre = [w / 2 * (1 + 0.1), h / 2 + w / 2 * 0.05]
    d, ok = lens.pixel_to_dir(np.array([centre]))
    assert ok[0] and np.abs(d[0] - [0, 0, 1]).max() < 1e-15
    # straight up from the circle's centre by half the image height: 75 degrees (vfov / 2)
    assert angle_from_pixel(lens, [centre[0], centre[1] - h / 2]) == pytest.approx(math.radians(75), abs=1e-12)
    # equisolid beyond: a = 2 asin(r sin(F/2)) with r in units of half the height, until r sin(F/2) = 1
    F = math.radians(75)
    r = 1.3
    want = 2 * math.asin(r * math.sin(F / 2))
    assert angle_from_pixel(lens, [centre[0] + r * h / 2, centre[1]]) == pytest.approx(want, abs=1e-12)
    _, ok = lens.pixel_to_dir(np.array([[centre[0] + 1.01 / math.sin(F / 2) * h / 2, centre[1]]]))
    assert not ok[0]  # where the mapping ends (180 degrees)
    # fov across the width keeps masking at the width's circle, as it always did
    assert not make_lens("fisheye:fov=180", (w, h)).pixel_to_dir(np.array([[5.0, 5.0]]))[1][0]


def test_perspective_dfov():
    w, h = 1200, 800
    lens = make_lens("perspective:dfov=100", (w, h))
    assert angle_from_pixel(lens, [0, 0]) == pytest.approx(math.radians(50), abs=1e-12)
    # square pixels: the horizontal half-angle is atan(tan(50 deg) w / diagonal)
    want = math.atan(math.tan(math.radians(50)) * w / math.hypot(w, h))
    assert angle_from_pixel(lens, [w, h / 2]) == pytest.approx(want, abs=1e-12)
