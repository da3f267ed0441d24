"""The 360 projections pinned against their published formulas (transcribed here in float64, from
Snyder's *Map Projections - A Working Manual* (USGS 1395, 1987) for the map projections and from
Sharpless, Postle and German (2010) for Pannini), their defining properties (equal area, conformal),
and the layouts of the cube maps, EAC and dual fisheye."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lenslab.lenses import make_lens


def direction(lon_deg: float, lat_deg: float) -> np.ndarray:
    lon, lat = math.radians(lon_deg), math.radians(lat_deg)
    return np.array([math.cos(lat) * math.sin(lon), math.sin(lat), math.cos(lat) * math.cos(lon)])


def pixel(spec, size, d):
    xy, ok = make_lens(spec, size).dir_to_pixel(np.asarray(d, dtype=float)[None])
    assert ok[0]
    return xy[0]


def to_pixel(u: float, v: float, size) -> np.ndarray:
    """Normalised (u, v) of docs/conventions.md to pixels."""
    w, h = size
    return np.array([w / 2 * (1 + u), h / 2 - w / 2 * v])


LONLAT = [(0.0, 0.0), (30.0, 20.0), (-120.0, 45.0), (170.0, -60.0), (-5.0, -80.0)]


@pytest.mark.parametrize("lon,lat", LONLAT)
def test_cylindrical_family_against_snyder(lon, lat):
    size = (720, 720)
    F = math.pi  # fov 360
    phi, th = math.radians(lon), math.radians(lat)
    # central cylindrical: y = tan(lat); Lambert's equal-area cylinder: y = sin(lat) (Snyder eq. 10-1);
    # Mercator: y = ln tan(pi/4 + lat/2) (Snyder eq. 7-2); x = longitude for all three (radians)
    for spec, y in (("cylindrical", math.tan(th)), ("cylindrical-equal-area", math.sin(th)),
                    ("mercator", math.log(math.tan(math.pi / 4 + th / 2)))):
        want = to_pixel(phi / F, y / F, size)
        lens = make_lens(spec, size)
        xy, ok = lens.dir_to_pixel(direction(lon, lat)[None])
        if ok[0]:
            assert np.abs(xy[0] - want).max() < 1e-9, spec  # 1e-9 px: float64 rounding at 720 px
        else:  # outside the frame (the cylinder's tan and Mercator's log grow past the square)
            assert not (0 <= want[1] <= size[1]), spec


def test_vfov_sets_the_latitude_at_the_top_edge():
    # v360's cylindrical-equal-area spans sin(lat) = -1..1 over the height: the poles on the edges
    lens = make_lens("cylindrical-equal-area:vfov=180", (400, 200))
    assert np.abs(pixel("cylindrical-equal-area:vfov=180", (400, 200), [0, 1, 0]) - [200, 0]).max() < 1e-12
    # Mercator with vfov: ln tan(pi/4 + lat/2) over that of vfov/2 runs -1..1 over the height
    top = math.log(math.tan(math.pi / 4 + math.radians(75) / 2))
    y = math.log(math.tan(math.pi / 4 + math.radians(40) / 2))
    want = 100 * (1 - y / top)
    assert pixel("mercator:vfov=150", (400, 200), direction(0, 40))[1] == pytest.approx(want, abs=1e-9)
    assert lens.pixel_to_dir(np.array([[200.0, 0.0]]))[1][0]


@pytest.mark.parametrize("d,fov,vcomp", [(1.0, 150.0, 0.0), (0.5, 200.0, 0.0), (2.0, 239.9, 0.0), (1.0, 120.0, 0.6)])
def test_pannini_against_sharpless(d, fov, vcomp):
    size = (800, 500)
    F = math.radians(fov) / 2
    S = lambda phi: (d + 1) / (d + math.cos(phi))  # noqa: E731  (Sharpless et al. 2010, eq. 1)
    x_f = S(F) * math.sin(F)
    for lon, lat in ((0.0, 0.0), (40.0, 10.0), (-0.8 * fov / 2, -25.0), (fov / 2 - 1, 5.0)):
        phi, th = math.radians(lon), math.radians(lat)
        x = S(phi) * math.sin(phi)
        y = S(phi) * math.tan(th)  # eq. 2; vertical compression takes (S - 1) back by vcomp
        y *= (1 + (1 - vcomp) * (S(phi) - 1)) / S(phi)
        want = to_pixel(x / x_f, y / x_f, size)
        assert np.abs(pixel(f"pannini:d={d},fov={fov},vcomp={vcomp}", size, direction(lon, lat)) - want).max() < 1e-9


def test_pannini_at_a_whole_turn_stays_finite_and_exact():
    # Classic Pannini (d = 1): x = 2 sin phi / (1 + cos phi) = 2 tan(phi / 2), the stereographic cylinder.
    # A field of view a hair under 360 degrees puts the edge where 1 + cos phi rounds to 0 in float64.
    fov, size = 360.0 - 1e-6, (800, 400)
    F = math.radians(fov) / 2
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no division by zero, no overflow
        lens = make_lens(f"pannini:d=1,fov={fov}", size)
        x_f = 2 * math.tan(F / 2)
        # 1e-12: tan and cos of the same float64 F / 2 each carry ~1 ulp; the rest is exact
        assert lens.x_f == pytest.approx(x_f, rel=1e-12)
        for lon in (0.0, 90.0, 170.0, 179.9):
            want = to_pixel(2 * math.tan(math.radians(lon) / 2) / x_f, 0.0, size)
            assert np.abs(pixel(f"pannini:d=1,fov={fov}", size, direction(lon, 0.0)) - want).max() < 1e-9
        xy = np.c_[np.linspace(0.0, 800.0, 81), np.full(81, 200.0)]
        d, ok = lens.pixel_to_dir(xy)
    assert ok.all() and np.isfinite(d).all()
    x = (xy[:, 0] / 400.0 - 1.0) * x_f  # u = 2 x / width - 1 (pixel edges at u = -1, 1)
    want = 2 * np.arctan(x / 2)  # the longitude whose 2 tan(phi / 2) is x
    # 1e-12 rad: atan2 of the closed-form inverse, ~1 ulp of pi in its cos(phi) near -1
    assert np.abs(np.arctan2(d[:, 0], d[:, 2]) - want).max() < 1e-12


def test_pannini_with_d_0_is_the_perspective_view():
    rng = np.random.default_rng(2)
    xy = rng.random((500, 2)) * (640, 480)
    a, _ = make_lens("pannini:d=0,fov=100", (640, 480)).pixel_to_dir(xy)
    b, _ = make_lens("perspective:fov=100", (640, 480)).pixel_to_dir(xy)
    assert np.abs(a - b).max() < 1e-13


def test_pannini_keeps_verticals_straight():
    lens = make_lens("pannini:d=1,fov=200,vcomp=0.4", (1000, 600))
    for x in (50.0, 300.0, 930.0):
        d, ok = lens.pixel_to_dir(np.c_[np.full(40, x), np.linspace(0, 600, 40)])
        assert ok.all()
        # every direction of an image column lies in one vertical plane: one longitude
        lon = np.arctan2(d[:, 0], d[:, 2])
        assert np.ptp(lon) < 1e-12


@pytest.mark.parametrize("lon,lat", LONLAT)
def test_hammer_and_sinusoidal_against_snyder(lon, lat):
    size = (1000, 500)
    phi, th = math.radians(lon), math.radians(lat)
    # Hammer: x = 2 sqrt2 cos(lat) sin(lon/2) / sqrt(1 + cos(lat) cos(lon/2)), y = sqrt2 sin(lat) / sqrt(..)
    den = math.sqrt(1 + math.cos(th) * math.cos(phi / 2))
    x = 2 * math.sqrt(2) * math.cos(th) * math.sin(phi / 2) / den
    y = math.sqrt(2) * math.sin(th) / den
    want = to_pixel(x / (2 * math.sqrt(2)), y / (2 * math.sqrt(2)), size)
    assert np.abs(pixel("hammer", size, direction(lon, lat)) - want).max() < 1e-9
    # sinusoidal: x = lon cos(lat), y = lat (Snyder eq. 30-1, 30-2), pi to the half width
    want = to_pixel(phi * math.cos(th) / math.pi, th / math.pi, size)
    assert np.abs(pixel("sinusoidal", size, direction(lon, lat)) - want).max() < 1e-9


def solid_angle_density(lens, xy, h=1e-3):
    dx = (lens.pixel_to_dir(xy + [h, 0])[0] - lens.pixel_to_dir(xy - [h, 0])[0]) / (2 * h)
    dy = (lens.pixel_to_dir(xy + [0, h])[0] - lens.pixel_to_dir(xy - [0, h])[0]) / (2 * h)
    return np.linalg.norm(np.cross(dx, dy), axis=-1), dx, dy


@pytest.mark.parametrize("spec,size,area_px", [
    ("hammer", (1000, 500), math.pi * 500 * 250),          # the ellipse holds the sphere
    ("sinusoidal", (1000, 500), 4 * math.pi * (500 / math.pi) ** 2),  # 4 pi R^2 with R = W / (2 pi) px
    ("cylindrical-equal-area", (1000, 318), 1000 * 1000 / math.pi),  # lat -90..90: y = +-W/(2 pi)
])
def test_equal_area_maps_hold_equal_solid_angle(spec, size, area_px):
    lens = make_lens(spec, size)
    rng = np.random.default_rng(5)
    xy = rng.random((4000, 2)) * size
    _, ok = lens.pixel_to_dir(xy)
    inner = ok.copy()
    for a in np.arange(8) * np.pi / 4:  # away from the outline, where the differences would straddle it
        inner &= lens.pixel_to_dir(xy + 3 * np.array([np.cos(a), np.sin(a)]))[1]
    density, _, _ = solid_angle_density(lens, xy[inner])
    # 4 pi steradians over the map's area; 1e-6: central differences with h = 1e-3 px
    assert np.abs(density / (4 * math.pi / area_px) - 1).max() < 1e-6


@settings(max_examples=30, deadline=None)
@given(x=st.floats(5.0, 995.0), y=st.floats(5.0, 995.0))
def test_mercator_is_conformal(x, y):
    lens = make_lens("mercator", (1000, 1000))
    _, dx, dy = solid_angle_density(lens, np.array([[x, y]]))
    lx, ly = np.linalg.norm(dx), np.linalg.norm(dy)
    # 1e-6: central differences with h = 1e-3 px
    assert abs(lx / ly - 1) < 1e-6 and abs(np.dot(dx[0], dy[0])) / (lx * ly) < 1e-6


def test_half_equirect_and_little_planet():
    assert np.abs(pixel("half-equirect", (600, 600), direction(45, 30)) - [600 * 0.75, 300 * (1 - 30 / 90)]).max() < 1e-9
    # little planet: looking straight down, stereographic, forward at the top; the horizon (90 degrees
    # from the nadir) at r = tan(45) / tan(fov/4)
    size = (800, 800)
    assert np.abs(pixel("little-planet", size, [0, -1, 0]) - [400, 400]).max() < 1e-9
    r = 1 / math.tan(math.radians(270) / 4)
    assert np.abs(pixel("little-planet", size, [0, 0, 1]) - [400, 400 - 400 * r]).max() < 1e-9
    assert np.abs(pixel("little-planet", size, [1, 0, 0]) - [400 + 400 * r, 400]).max() < 1e-9


# -- piecewise layouts --------------------------------------------------------------------------
def centre_direction(spec, size, cell, grid):
    cw, ch = size[0] / grid[0], size[1] / grid[1]
    d, ok = make_lens(spec, size).pixel_to_dir(np.array([[(cell[0] + 0.5) * cw, (cell[1] + 0.5) * ch]]))
    return d[0], ok[0]


def test_cube_layouts_put_each_face_where_they_say():
    axes = {"r": [1, 0, 0], "l": [-1, 0, 0], "u": [0, 1, 0], "d": [0, -1, 0], "f": [0, 0, 1], "b": [0, 0, -1]}
    for k, face in enumerate("rludfb"):  # 1x6: ffmpeg's c1x6, faces top to bottom
        d, ok = centre_direction("cubemap:layout=1x6", (100, 600), (0, k), (1, 6))
        assert ok and np.abs(d - axes[face]).max() < 1e-15
    cross = {(1, 0): "u", (0, 1): "l", (1, 1): "f", (2, 1): "r", (3, 1): "b", (1, 2): "d"}
    for cell in np.ndindex(4, 3):
        d, ok = centre_direction("cubemap:layout=4x3", (400, 300), cell, (4, 3))
        assert ok == (cell in cross)
        if ok:
            assert np.abs(d - axes[cross[cell]]).max() < 1e-15
    # the cross folds into a cube: the up face's bottom edge is the front face's top edge, pixel for pixel
    lens = make_lens("cubemap:layout=4x3", (400, 300))
    a, _ = lens.pixel_to_dir(np.array([[130.0, 100.0 - 1e-9], [170.0, 100.0 - 1e-9]]))
    b, _ = lens.pixel_to_dir(np.array([[130.0, 100.0], [170.0, 100.0]]))
    assert np.abs(a - b).max() < 1e-10


def test_eac_spaces_pixels_evenly_in_angle():
    w, h = 600, 400
    # front face (top middle): a direction 30 degrees right of the axis in the horizontal plane sits at
    # s = 30/45 of the face's half width (equal angles, where a cube map would put tan(30) = 0.577)
    xy = pixel("eac", (w, h), direction(30, 0))
    assert xy == pytest.approx([w / 3 * (1 + (1 + 30 / 45) / 2), h / 4], abs=1e-9)
    # with v360's 2-pixel pad: the faces share the width less 4 px and each row less 4 px
    xy = pixel("eac:pad=2", (w, h), direction(30, 0))
    assert xy == pytest.approx([2 + (w - 4) / 3 * (1 + (1 + 30 / 45) / 2), 2 + (h / 2 - 4) / 2], abs=1e-9)
    # the bottom row runs along the back (turned a quarter): its centre is -z, its left neighbour -y
    for cell, want in (((1, 1), [0, 0, -1]), ((0, 1), [0, -1, 0]), ((2, 1), [0, 1, 0]), ((0, 0), [-1, 0, 0])):
        d, ok = centre_direction("eac", (w, h), cell, (3, 2))
        assert ok and np.abs(d - want).max() < 1e-15


def test_dual_fisheye_reads_the_overlap_from_the_nearer_lens():
    w, h = 800, 400
    # 100 degrees off the front axis toward +x (inside both 200-degree circles): read from the back lens,
    # 80 degrees off its axis at r = 80/100, on its left (the back lens's right is -x)
    d = direction(100, 0)
    assert pixel("dual-fisheye:fov=200", (w, h), d) == pytest.approx([w / 2 + w / 4 * (1 - 0.8), h / 2], abs=1e-9)
    assert pixel("dual-fisheye:fov=200,front=right", (w, h), d) == pytest.approx([w / 4 * (1 - 0.8), h / 2], abs=1e-9)
    # as an output each half is one whole fisheye: the left half's rim, 100 degrees off the front axis
    lens = make_lens("dual-fisheye:fov=200", (w, h))
    out, ok = lens.pixel_to_dir(np.array([[w / 2 - 1e-9, h / 2], [0.0, h / 2]]))
    assert ok.all() and np.abs(out - [direction(100, 0), direction(-100, 0)]).max() < 1e-8


def test_dual_fisheye_blend_weights_fall_to_zero_at_each_rim():
    lens = make_lens("dual-fisheye:fov=200", (800, 400))
    F = math.radians(100)
    band = 2 * F - math.pi
    rng = np.random.default_rng(4)
    d = rng.normal(size=(5000, 3))
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    views = lens.blend_views(d)
    a_front = np.arccos(np.clip(d[:, 2], -1, 1))
    for k, (xy, ok, w) in enumerate(views):
        a = a_front if k == 0 else math.pi - a_front
        # the smoothstep of the margin to the rim across the overlap, transcribed: 3w^2 - 2w^3
        m = np.clip((F - a) / band, 0, 1)
        assert np.abs(w - (3 * m**2 - 2 * m**3)).max() < 1e-12
        # each reading is a pixel of that lens that sees the direction
        back, _ = lens.pixel_to_dir(xy[ok])
        assert np.abs(back - d[ok]).max() < 1e-12
        assert ((xy[ok, 0] < 400) == (k == 0)).all()  # front lens on the left half
    assert np.abs(views[0][2] + views[1][2] - 1).max() < 1e-15


def test_octahedron_folds_the_back_into_the_corners():
    size = (400, 400)
    # front: (x, y) / (|x| + |y| + |z|); the octahedral encoding of normals (Meyer et al. 2010, v360's octahedron)
    d = np.array([0.3, 0.5, 0.8])
    assert np.abs(pixel("octahedron", size, d) - to_pixel(0.3 / 1.6, 0.5 / 1.6, size)).max() < 1e-9
    # back: the same point folded out, ((1 - |y|) sign x, (1 - |x|) sign y)
    d = np.array([0.3, -0.5, -0.8])
    x, y = 0.3 / 1.6, -0.5 / 1.6
    assert np.abs(pixel("octahedron", size, d) - to_pixel(1 - abs(y), -(1 - abs(x)), size)).max() < 1e-9


def edge_point(piece, edge: int, s: float, depth: float) -> np.ndarray:
    """The point ``depth`` px inside edge ``edge`` (left, right, top, bottom) of a piece, at position ``s``
    along it (top to bottom on left/right edges, left to right on top/bottom ones)."""
    x0, y0, w, h = piece.rect
    return np.array([(x0 + depth, y0 + s), (x0 + w - depth, y0 + s), (x0 + s, y0 + depth), (x0 + s, y0 + h - depth)][edge])


@pytest.mark.parametrize("spec,size", [("eac", (600, 400)), ("eac:pad=2", (592, 400)), ("octahedron", (300, 300))])
def test_what_lies_across_each_piece_edge_is_its_neighbour_on_the_sphere(spec, size):
    """Half a pixel inside an edge and half a pixel inside what its piece says lies across it are one
    pixel apart on the sphere (to 1.5 pixels' angle: the spacing changes a little across an edge); any
    other edge or direction along it is tens of pixels away."""
    lens = make_lens(spec, size)
    pieces = lens.pieces()
    checked = 0
    for piece in pieces:
        for edge, other in enumerate(piece.across):
            if other is None:
                continue
            length = piece.height if edge < 2 else piece.width
            for s in np.array([0.2, 0.5, 0.85]) * length:
                here, step = edge_point(piece, edge, s, 0.5), edge_point(piece, edge, s, 1.5)
                t = length - s if other.reversed else s
                there = edge_point(pieces[other.piece], other.edge, t, 0.5)
                (d_here, d_step, d_there), ok = lens.pixel_to_dir(np.array([here, step, there]))
                assert ok.all()
                pixel_angle = np.arccos(np.clip(d_here @ d_step, -1, 1))
                assert np.arccos(np.clip(d_here @ d_there, -1, 1)) < 1.5 * pixel_angle, (piece, edge, s)
                checked += 1
    assert checked >= (12 if spec == "octahedron" else 72)


def test_full_turn_cylinders_wrap_and_lambert_reaches_its_poles():
    for spec, poles in (("cylindrical", False), ("mercator", False), ("cylindrical-equal-area:vfov=180", True)):
        lens = make_lens(spec, (400, 200))
        seams = lens.seams()
        assert seams.period_x == 400 and seams.pole_top == seams.pole_bottom == poles
        # the left and right edges are one meridian (the back, longitude 180)
        (a, b), ok = lens.pixel_to_dir(np.array([[0.0, 70.0], [400.0, 70.0]]))
        assert ok.all() and np.abs(a - b).max() < 1e-15 and a[2] < 0
    assert not make_lens("cylindrical:fov=180", (400, 200)).seams().wraps
    # the two halves of a dual fisheye are separate pieces with nothing across their edges
    halves = make_lens("dual-fisheye", (400, 200)).pieces()
    assert [p.rect for p in halves] == [(0, 0, 200, 200), (200, 0, 200, 200)] and all(p.across is None for p in halves)


@pytest.mark.parametrize("spec", ["cylindrical:fov=300,vfov=120", "cylindrical-equal-area:vfov=180", "mercator",
                                  "mercator:fov=200,vfov=150"])
def test_cylinder_column_scale_is_the_ratio_of_steps_on_the_sphere(spec):
    """One column step over one row step, both measured on the sphere by finite differences."""
    lens = make_lens(spec, (400, 200))
    ys = np.array([20.5, 60.5, 100.0, 170.25])
    h = 1e-4
    pts = np.stack([np.full_like(ys, 150.0), ys], -1)
    d0 = lens.pixel_to_dir(pts)[0]
    dxs = lens.pixel_to_dir(pts + [h, 0])[0]
    dys = lens.pixel_to_dir(pts + [0, h])[0]
    want = np.linalg.norm(dxs - d0, axis=-1) / np.linalg.norm(dys - d0, axis=-1)
    # 1e-5 relative: one-sided differences with h = 1e-4 px
    assert np.allclose(lens.column_scale(ys), want, rtol=1e-5)
