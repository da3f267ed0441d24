"""Lens models at their extremes: tiny and huge fields of view, the equirect seam and poles, swirl at
radius 0 and amounts 0 and 1000, distortion at and beyond its fold-over, the seed fisheye from 115 to
180 degrees, and garbage in (NaN, inf, zero vectors) without NaN or inf out.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lenslab.errors import LensError
from lenslab.lenses import make_lens
from tests.lenses.test_lenses_roundtrip import CASES, PX_TOL, angle, excluded, sample_pixels, shared_pixels

FOVS = (1e-3, 1.0, 179.9, 180.0, 270.0, 360.0)
FOV_MODELS = (
    "perspective", "fisheye:mapping=equidistant", "fisheye:mapping=equisolid",
    "fisheye:mapping=stereographic", "fisheye:mapping=orthographic", "tan-fisheye",
    "swirl:amount=6", "pincushion:k1=0.3", "brown:k1=-0.05",
)
#: the fovs each model allows (the others must be refused with a LensError)
ALLOWED = {
    "perspective": lambda f: f < 180, "tan-fisheye": lambda f: f <= 180,
    "fisheye:mapping=equidistant": lambda f: f <= 360, "fisheye:mapping=equisolid": lambda f: f <= 360,
    "fisheye:mapping=stereographic": lambda f: f < 360, "fisheye:mapping=orthographic": lambda f: f <= 180,
    "swirl:amount=6": lambda f: f < 180, "pincushion:k1=0.3": lambda f: f < 180, "brown:k1=-0.05": lambda f: f < 180,
}


def with_fov(model, fov):
    return f"{model}{',' if ':' in model else ':'}fov={fov!r}"


@pytest.mark.parametrize("model", FOV_MODELS)
@pytest.mark.parametrize("fov", FOVS)
def test_fov_extremes(model, fov):
    size = (4096, 4096)
    spec = with_fov(model, fov)
    if not ALLOWED[model](fov):
        with pytest.raises(LensError):
            make_lens(spec, size)
        return
    lens = make_lens(spec, size)
    xy = sample_pixels(size, n=4000)
    d, valid = lens.pixel_to_dir(xy)
    assert np.isfinite(d).all() and (d[~valid] == 0).all()
    assert valid.any()
    back, ok = lens.dir_to_pixel(d)
    assert np.isfinite(back).all()
    assert ok[valid].all()
    keep = valid & ~excluded(lens, xy) & ~shared_pixels(lens, xy)
    assert np.abs(back - xy)[keep].max() < PX_TOL
    centre, ok = lens.pixel_to_dir([[2048.0, 2048.0]])
    assert ok[0] and np.array_equal(centre[0], [0.0, 0.0, 1.0])


# -- equirect seam and poles ---------------------------------------------------------------------
def test_equirect_poles_exact_and_finite():
    lens = make_lens("equirect", (1024, 512))
    xs = np.linspace(0, 1024, 1001)
    top, ok_t = lens.pixel_to_dir(np.c_[xs, np.zeros_like(xs)])
    bottom, ok_b = lens.pixel_to_dir(np.c_[xs, np.full_like(xs, 512.0)])
    assert ok_t.all() and ok_b.all()
    assert (top == [0.0, 1.0, 0.0]).all() and (bottom == [0.0, -1.0, 0.0]).all()  # latitude exactly +-90
    # and back: the poles land exactly on the top and bottom edges
    xy, ok = lens.dir_to_pixel([[0.0, 1.0, 0.0], [0.0, -1.0, 0.0], [0.0, 1e-150, 0.0]])
    assert ok.all() and xy[0, 1] == 0.0 and xy[1, 1] == 512.0 and np.isfinite(xy).all()
    # a sliver from the pole: latitude within 1e-12 of 90 degrees, no NaN
    near, ok = lens.pixel_to_dir([[3.0, 1e-9], [1000.0, 512 - 1e-9]])
    assert ok.all() and np.isfinite(near).all()
    assert np.degrees(np.arcsin(near[0, 1])) > 90 - 1e-6


@settings(max_examples=60, deadline=None)
@given(y=st.floats(0.0, 512.0), eps=st.floats(1e-9, 0.5))
def test_equirect_seam_is_continuous(y, eps):
    """Pixels on either side of the seam map to neighbouring directions (a step of 2 eps pixels)."""
    lens = make_lens("equirect", (1024, 512))
    d, ok = lens.pixel_to_dir([[eps, y], [1024 - eps, y], [0.0, y], [1024.0, y]])
    assert ok.all()
    step = 2 * eps * 2 * np.pi / 1024  # longitude step across the seam, radians
    # distance on the sphere <= the longitude step (smaller off the equator); 1e-15 for rounding
    assert angle(d[0], d[1]) <= step + 1e-15
    assert angle(d[2], d[3]) < 1e-15  # the two edges are the same meridian


def test_equirect_partial_range_refuses_outside():
    lens = make_lens("equirect:lon_min=-90,lon_max=90,lat_min=-45,lat_max=45", (1000, 500))
    xy, ok = lens.dir_to_pixel([[0, 0, -1], [0, 1, 0], [0, 0, 1], [1, 0, 0]])
    assert list(ok) == [False, False, True, True]
    assert np.allclose(xy[2], [500, 250]) and np.allclose(xy[3], [1000, 250])


# -- swirl ---------------------------------------------------------------------------------------
@pytest.mark.parametrize("amount", [0.0, 6.0, 1000.0, -1000.0])
def test_swirl_centre_and_extreme_amounts(amount):
    size = (8192, 4608)
    lens = make_lens(f"swirl:amount={amount}", size)
    d, ok = lens.pixel_to_dir([[4096.0, 2304.0]])
    assert ok[0] and np.array_equal(d[0], [0.0, 0.0, 1.0])  # radius 0: no turn, exactly +z
    xy = sample_pixels(size, n=20000)
    d, ok = lens.pixel_to_dir(xy)
    assert np.isfinite(d).all() and ok.all()
    back, ok2 = lens.dir_to_pixel(d)
    assert ok2.all()
    # amount 1000 turns the corners by ~1150 rad; its rounding (1150 * 1.1e-16 rad at 4700 px from the
    # centre) is ~6e-10 px, well inside the 1e-6 px table value
    assert np.abs(back - xy).max() < PX_TOL


def test_swirl_zero_is_its_base():
    xy = sample_pixels((640, 480), n=2000)
    for base in ("perspective:fov=100", "fisheye:fov=200,mapping=equisolid"):
        name, _, params = base.partition(":")
        plain = make_lens(base, (640, 480))
        swirl = make_lens(f"swirl:amount=0,base={name},{params}", (640, 480))
        a, b = plain.pixel_to_dir(xy), swirl.pixel_to_dir(xy)
        assert np.array_equal(a[1], b[1]) and np.array_equal(a[0], b[0])


def test_swirl_turns_counter_clockwise_by_rho_amount():
    lens = make_lens("swirl:amount=0.5,fov=90", (1000, 1000))
    # u = 0.5 on the x axis turns by 0.25 rad toward +y
    d, _ = lens.pixel_to_dir([[750.0, 500.0]])
    assert np.isclose(np.arctan2(d[0, 1], d[0, 0]), 0.25, atol=1e-14)


# -- distortion fold-over ------------------------------------------------------------------------
def radius_pixels(lens, radii):
    """Pixels on the +u axis whose normalised radius is the first float64 pixel at or past each radius."""
    x = (np.asarray(radii, dtype=float) + 1) * lens.width / 2
    for i, r in enumerate(radii):
        while 2 * x[i] / lens.width - 1 < r:
            x[i] = np.nextafter(x[i], np.inf)
    return np.c_[x, np.full(len(radii), lens.height / 2)]


@pytest.mark.parametrize("spec,r_fold", [
    ("pincushion:k1=1.0", 1.0),                       # dr_u/dr_d = (1 - s)/(1 + s)^2: fold at r = 1
    ("pincushion:k1=0.3,k2=0.5", np.sqrt((-0.3 + np.sqrt(0.09 + 6.0)) / 3.0)),  # 1 - 0.3 s - 1.5 s^2 = 0
    ("barrel:k1=-1.0", 1.0),                          # denominator 1 - s reaches 0 at r = 1
    ("distortion:k1=-0.2,k2=0.3", None),              # computed below from the closed form
])
def test_distortion_at_and_beyond_fold_is_invalid(spec, r_fold):
    lens = make_lens(spec, (2000, 2000))
    if r_fold is not None:
        assert np.isclose(lens.r_fold, r_fold, rtol=1e-14)
    r_fold = lens.r_fold  # the float64 the model tests against
    radii = np.array([0.0, 0.5 * r_fold, r_fold * (1 - 1e-9), r_fold, r_fold * (1 + 1e-9), 1.2 * r_fold])
    inside_image = radii <= 1.0
    d, ok = lens.pixel_to_dir(radius_pixels(lens, radii))
    assert np.isfinite(d).all()
    assert list(ok[:3]) == [True, True, True] or not inside_image[2]
    assert not ok[3:].any()  # at the fold and beyond: invalid, and zero
    assert (d[3:] == 0).all()
    # the slope really changes sign (or the radius diverges) at r_fold
    r_u, slope = lens.radius_map(np.array([r_fold * (1 - 1e-6), r_fold * (1 + 1e-6)]))
    assert slope[0] > 0 and (slope[1] < 0 or r_u[1] == np.inf)  # a fold, or past a pole
    # directions beyond the largest undistorted radius are refused by the inverse
    r_max, _ = lens.radius_map(np.array([r_fold * (1 - 1e-12)]))
    for r_u_target, expect in ((0.5 * r_max[0], True), (r_max[0] * (1 + 1e-6), False), (10 * r_max[0] + 10, False)):
        bent = np.array([[r_u_target, 0.0]])
        dirs, _ = lens.base_lens.uv_to_dir(bent)
        xy, seen = lens.dir_to_pixel(dirs)
        if expect:
            assert seen[0] or xy[0, 0] == 0  # seen unless it falls outside the image
        else:
            assert not seen[0] and (xy[0] == 0).all()


def test_brown_fold_is_invalid():
    lens = make_lens("brown:k1=-0.3", (2000, 2000))
    ru_fold = np.sqrt(1 / 0.9)  # 1 + 3 k1 s = 0
    rd_fold = ru_fold * (1 - 0.3 * ru_fold ** 2)
    assert np.isclose(lens.rd_fold, rd_fold, rtol=1e-14)
    d, ok = lens.pixel_to_dir(radius_pixels(lens, [0.5 * rd_fold, rd_fold * (1 - 1e-9), rd_fold, 0.99]))
    assert list(ok) == [True, True, False, False] and np.isfinite(d).all() and (d[2:] == 0).all()
    # directions whose ideal radius lies beyond the fold are refused
    dirs, _ = lens.base_lens.uv_to_dir(np.array([[ru_fold * 1.01, 0.0]]))
    assert not lens.dir_to_pixel(dirs)[1][0]


# -- the seed fisheye from 115 to 180 degrees ----------------------------------------------------
def seed_reference(u, v, fov):
    """The seed renderer's code, transcribed literally (float64), then normalised."""
    r_norm = np.sqrt(u * u + v * v)
    radius = r_norm * np.radians(fov) * 0.5
    distorted = np.tan(radius)
    d = np.stack([np.sin(distorted) * u, np.sin(distorted) * v, np.cos(distorted)], axis=-1)
    return d / np.linalg.norm(d, axis=-1, keepdims=True), r_norm


@pytest.mark.parametrize("fov", [115.0, 120.0, 144.6, 144.8, 150.0, 170.0, 179.0, 180.0])
def test_seed_fisheye_reproduces_and_masks_the_fold(fov):
    lens = make_lens(f"tan-fisheye:fov={fov}", (2048, 2048))
    xy = sample_pixels((2048, 2048), n=20000)
    d, ok = lens.pixel_to_dir(xy)
    assert np.isfinite(d).all()
    uv = lens.pixel_to_uv(xy)
    ref, r = seed_reference(uv[:, 0], uv[:, 1], fov)
    F = np.radians(fov) / 2
    r_fold = np.arctan(np.pi) / F  # t = tan(r F) reaches pi
    expect = (r <= 1) & (r < r_fold)
    band = np.abs(r - min(1.0, r_fold)) < 1e-9  # rounding at the boundary itself
    assert (ok == expect)[~band].all()
    # the seed's directions, to rounding (the seed's own tan(r F) carries ~1e-16 relative error)
    assert angle(d[ok], ref[ok]).max() < 1e-12
    # the angle from the axis increases along every radius up to the fold: no direction seen twice
    rr = np.linspace(0, min(1.0, r_fold) * (1 - 1e-9), 20001)
    dd, okr = lens.pixel_to_dir(np.c_[(rr + 1) * 1024, np.full_like(rr, 1024.0)])
    assert okr.all()
    assert (np.diff(np.arctan2(np.hypot(dd[:, 0], dd[:, 1]), dd[:, 2])) > 0).all()
    # and the round trip holds on the valid disc
    back, seen = lens.dir_to_pixel(d)
    assert seen[ok].all() and np.abs(back - xy)[ok].max() < PX_TOL
    # the rim (or the fold) passes 90 degrees from the axis once fov > 2 atan(pi/2) = 115.04 degrees
    assert (lens.max_angle > np.pi / 2) == (fov > 2 * np.degrees(np.arctan(np.pi / 2)))


def test_seed_fisheye_fold_threshold():
    """Folds exactly when tan(F) > pi: fov 2 atan(pi) = 144.7 degrees."""
    threshold = 2 * np.degrees(np.arctan(np.pi))
    assert not make_lens(f"tan-fisheye:fov={threshold - 1e-6}", (64, 64)).folds
    assert make_lens(f"tan-fisheye:fov={threshold + 1e-6}", (64, 64)).folds


# -- garbage in, no NaN out ----------------------------------------------------------------------
@pytest.mark.parametrize("spec,size", CASES, ids=[c[0] for c in CASES])
def test_no_nan_or_inf_ever_leaves_a_model(spec, size):
    lens = make_lens(spec, size)
    bad_xy = np.array([[np.nan, 1.0], [1.0, np.inf], [-np.inf, 0.0], [1e308, 1e308], [-1e300, 5.0],
                       [-1.0, -1.0], [size[0] + 1.0, 0.0]])
    d, ok = lens.pixel_to_dir(bad_xy)
    assert np.isfinite(d).all() and not ok[:5].any() and (d[~ok] == 0).all()
    bad_d = np.array([[0.0, 0.0, 0.0], [np.nan, 0, 1], [np.inf, 0, 1], [1e-300, 0, 0], [1e300, 1e300, 1e300],
                      [-np.inf, -np.inf, -np.inf]])
    xy, ok = lens.dir_to_pixel(bad_d)
    assert np.isfinite(xy).all()
    assert not ok[[0, 1, 2, 5]].any() and (xy[~ok] == 0).all()
    # shapes: any leading shape in, the same out
    d, ok = lens.pixel_to_dir(np.zeros((2, 3, 4, 2)))
    assert d.shape == (2, 3, 4, 3) and ok.shape == (2, 3, 4)
    xy, ok = lens.dir_to_pixel(np.ones((5, 1, 3)))
    assert xy.shape == (5, 1, 2) and ok.shape == (5, 1)
