"""Round trips of every registered lens model: pixel -> direction -> pixel and direction -> pixel -> direction.

Pixels are drawn at random over the whole image (8192 px wide), plus the edges, the corners, the
centre and points just inside and outside the image circle; directions at random over the sphere,
keeping those the model sees. The tolerances, with their reasons, are in ``TOLERANCES`` below.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lenslab.lenses import REGISTRY, make_lens

W = 8192

#: (spec, (width, height)): the examples every registered model declares (its ``examples``), at 8192 px
#: width or so; a new model brings its own and is tested with no edit here
CASES = [case for entry in REGISTRY.entries() for case in entry.examples]


#: the one table of tolerances. Pixel errors are in pixels at 8192 px width, direction errors in radians.
TOLERANCES = {
    "pixel": (1e-6, "the required accuracy; the closed forms reach ~1e-11 px and the numeric inverses "
                    "stop their Newton steps below 1e-13 of the half width (4e-10 px)"),
    "direction": (1e-12, "1e-12 rad is 3e-9 px even at the 1e-3 degree fov; float64 directions carry "
                         "~1e-16, the inverse solves 1e-13 of the half width"),
    "fov360 rim band": (0.01, "pixels within 0.01 px of the rim of a 360-degree fisheye are left out: the "
                              "whole rim is one direction (-z), and next to it the azimuth rests on "
                              "sin(pi - eps) ~ eps, whose rounding ~1e-16/eps grows past 1e-6 px there"),
    "orthographic rim": (3e-8, "an orthographic fisheye at fov 180 has da/dr = 1/sqrt(1 - r^2), infinite at the "
                               "rim: a rounding of 1e-16 in r there moves the angle by sqrt(2e-16) = 1.5e-8 rad "
                               "(the pixel error stays tiny); used for directions of pixels with r > 1 - 1e-6"),
    "ball rim": (6e-8, "the ball's angle 2 asin(r) (and the globe's) has an infinite slope at the rim, twice the "
                       "orthographic fisheye's: a rounding of 1e-16 in r moves it by 2 sqrt(2e-16) = 3e-8 rad, "
                       "plus the rounding of the radius itself; used within 1e-6 of the rim"),
    "equal-area pole": (3e-8, "Lambert's cylinder spaces latitude by its sine, so d(theta)/dv is infinite at a "
                              "pole: a rounding of 1e-16 in v there moves the latitude by sqrt(2e-16) = 1.5e-8 "
                              "rad; used for directions within 1e-12 of a pole"),
    "shared pixels": (None, "some directions have several pixels: an equirect pole (its whole top or bottom "
                            "row) and seam (left and right edges), a cube edge or a tile border (one pixel "
                            "in each face or tile); there the round trip is checked on the direction"),
}
PX_TOL = TOLERANCES["pixel"][0]
DIR_TOL = TOLERANCES["direction"][0]
RIM_BAND = TOLERANCES["fov360 rim band"][0]


@pytest.mark.parametrize("name", list(REGISTRY))
def test_every_registered_model_brings_examples_of_itself(name):
    examples = REGISTRY.entry(name).examples
    assert examples, f"{name}: give the class an examples tuple of (spec, (width, height))"
    assert all(REGISTRY.canonical(spec.partition(":")[0]) == name for spec, _ in examples)
    assert all(make_lens(spec, size).name == name for spec, size in examples)


def sample_pixels(size, n=20000, seed=0):
    """Random pixels plus every edge, corner, the centre and pixel centres along the edges."""
    w, h = size
    rng = np.random.default_rng(seed)
    pts = [rng.random((n, 2)) * (w, h)]
    t = rng.random(200)
    pts += [np.c_[t * w, np.zeros(200)], np.c_[t * w, np.full(200, h)],
            np.c_[np.zeros(200), t * h], np.c_[np.full(200, w), t * h]]
    pts.append(np.array([[0, 0], [w, 0], [0, h], [w, h], [w / 2, h / 2], [0.5, 0.5], [w - 0.5, h - 0.5]],
                        dtype=float))
    # points on the image circle of circular models, just inside it and just outside
    a = rng.random(300) * 2 * np.pi
    for r in (1.0 - 1e-9, 1.0, 1.0 + 1e-9):
        pts.append(np.c_[w / 2 * (1 + r * np.cos(a)), h / 2 - w / 2 * r * np.sin(a)])
    pts = np.concatenate(pts)
    inside = (pts[:, 0] >= 0) & (pts[:, 0] <= w) & (pts[:, 1] >= 0) & (pts[:, 1] <= h)
    return pts[inside]


def excluded(lens, xy):
    """Pixels left out of the pixel comparison (see TOLERANCES)."""
    out = np.zeros(xy.shape[0], dtype=bool)
    if lens.name == "fisheye" and lens.fov == 360:
        u = lens.pixel_to_uv(xy)
        out |= np.hypot(u[:, 0], u[:, 1]) > 1 - RIM_BAND * 2 / lens.width
    return out


def angle(a, b):
    """Angle between unit vectors, accurate for tiny angles."""
    return 2 * np.arcsin(np.clip(np.linalg.norm(a - b, axis=-1) / 2, 0, 1))


@pytest.mark.parametrize("spec,size", CASES, ids=[c[0] for c in CASES])
def test_pixel_direction_pixel(spec, size):
    lens = make_lens(spec, size)
    xy = sample_pixels(size)
    d, valid = lens.pixel_to_dir(xy)
    assert np.isfinite(d).all() and d.dtype == np.float64
    assert np.allclose(np.linalg.norm(d[valid], axis=-1), 1.0, atol=1e-15 * 8)  # unit within a few ulps
    assert valid.mean() > 0.3  # the samples really exercise the model
    back, ok = lens.dir_to_pixel(d)
    assert np.isfinite(back).all()
    # every valid pixel's direction is seen again
    assert ok[valid].all(), xy[valid & ~ok][:5]
    err = np.abs(back - xy).max(axis=-1)
    keep = valid & ~excluded(lens, xy)
    # shared pixels: compare directions there, pixels elsewhere
    d2, ok2 = lens.pixel_to_dir(back)
    assert ok2[keep].all()
    assert (angle(d2[keep], d[keep]) < direction_tolerance(lens, xy[keep])).all()
    keep &= ~shared_pixels(lens, xy)
    assert err[keep].max() < PX_TOL, (err[keep].max(), xy[keep][np.argmax(err[keep])])


def direction_tolerance(lens, xy):
    """Per-pixel direction tolerance (radians) from TOLERANCES."""
    tol = np.full(xy.shape[0], DIR_TOL)
    if lens.name == "fisheye" and lens.mapping == "orthographic" and lens.fov == 180:
        u = lens.pixel_to_uv(xy)
        tol[np.hypot(u[:, 0], u[:, 1]) > 1 - 1e-6] = TOLERANCES["orthographic rim"][0]
    if lens.name == "cylindrical-equal-area":
        d, _ = lens.pixel_to_dir(xy)
        tol[np.abs(d[:, 1]) > 1 - 1e-12] = TOLERANCES["equal-area pole"][0]
    if lens.name in ("ball", "globe"):  # angles go as asin(r) or sqrt(1 - r^2): da/dr is infinite at the rim
        s = 2 * xy[:, 0] / lens.width - 1
        t = 1 - 2 * xy[:, 1] / lens.height
        tol[np.hypot(s, t) > 1 - 1e-6] = TOLERANCES["ball rim"][0]
    return tol


def barrel_shared(lens, xy):
    """Facebook's barrels: the 1% margins round each part repeat directions shown elsewhere, a cap's
    corners (beyond 45 degrees from its pole) are read from the band, and the parts' edges are shared."""
    d, _ = lens.pixel_to_dir(xy)
    lat = np.degrees(np.arcsin(np.clip(np.abs(d[:, 1]), 0, 1)))
    out = np.zeros(xy.shape[0], dtype=bool)
    for p in lens.pieces():  # on a part's edge
        inside = (xy[:, 0] >= p.x0) & (xy[:, 0] <= p.x0 + p.width) & (xy[:, 1] >= p.y0) & (xy[:, 1] <= p.y0 + p.height)
        edge = np.minimum.reduce([np.abs(xy[:, 0] - p.x0), np.abs(xy[:, 0] - p.x0 - p.width),
                                  np.abs(xy[:, 1] - p.y0), np.abs(xy[:, 1] - p.y0 - p.height)]) < 1e-6
        band = p.width > lens.width / 2
        if lens.name == "fb-barrel":
            s = 2 * (xy[:, 0] - p.x0) / p.width - 1
            t = 2 * (xy[:, 1] - p.y0) / p.height - 1
            margin = (np.abs(s) > 0.99) | (np.abs(t) >= 0.99)
        else:
            margin = np.zeros(xy.shape[0], dtype=bool)
        wrong_part = (lat >= 45 - 1e-9) if band else (lat <= 45 + 1e-9)
        out |= inside & (edge | margin | wrong_part)
    return out


def shared_pixels(lens, xy):
    """Pixels whose direction may have another pixel too (see TOLERANCES): equirect poles and seam,
    cube-face and tile edges (within 1e-6 px)."""
    x, y = xy[:, 0], xy[:, 1]
    if lens.name in ("tetrahedron", "tsp"):  # the top and bottom edges fold onto themselves
        return (y < 1e-6) | (y > lens.height - 1e-6) | (x < 1e-6) | (x > lens.width - 1e-6)
    if lens.name in ("fb-barrel", "fb-barrelsplit"):
        return barrel_shared(lens, xy)
    if lens.name == "stereo":  # the second eye repeats the first; within an eye, the base's shared pixels
        (w, h), second = lens.eye_size, (x >= lens.eye_size[0]) if lens.layout == "sbs" else (y >= lens.eye_size[1])
        local = xy - np.where(second[:, None], [[w, 0]] if lens.layout == "sbs" else [[0, h]], 0.0)
        return second | shared_pixels(lens.base_lens, local)

    def near(f, scale):  # on any face or tile edge, outer edges included
        return np.abs(f - np.round(f)) * scale < 1e-6

    if lens.name in ("equirect", "half-equirect"):
        out = np.zeros(x.shape, dtype=bool)
        if lens.lat_max == 90:
            out |= y == 0
        if lens.lat_min == -90:
            out |= y == lens.height
        if lens.wraps:
            out |= (x == 0) | (x == lens.width)
        return out
    if getattr(lens, "wraps", False):  # a full turn of longitude: the left and right edges are one meridian
        out = (x == 0) | (x == lens.width)
        if lens.name == "cylindrical-equal-area":  # a pole row, when the image reaches it, is one direction
            out |= np.abs(lens.pixel_to_dir(xy)[0][:, 1]) > 1 - 1e-12
        return out
    if lens.name == "eac":  # face edges; the faces span the width less the pad, and each row less its pad
        fw = lens.width * (1 - 2 * lens.pu) / 3
        fh = lens.height * (0.5 - 2 * lens.pv)
        row = np.floor(2 * y / lens.height)
        return near((x - lens.pad) / fw, fw) | near((y - lens.pad - row * lens.height / 2) / fh, fh)
    if lens.name == "dual-fisheye":  # the overlap, where both lenses see: a direction has two pixels
        d, _ = lens.pixel_to_dir(xy)
        back = (x >= lens.width / 2) == (lens.front == "left")
        return np.where(back, d[:, 2] > -1e-9, d[:, 2] < 1e-9) | near(x / (lens.width / 2), lens.width / 2)
    if lens.name == "octahedron":  # the square's edges fold onto themselves (the back's outline)
        return (x == 0) | (x == lens.width) | (y == 0) | (y == lens.height)
    if lens.name in ("hammer", "sinusoidal"):  # the outline is the back meridian, seen from both sides
        d, _ = lens.pixel_to_dir(xy)
        return (np.abs(d[:, 0]) < 1e-9) & (d[:, 2] < 0)
    if lens.name not in ("cubemap", "tiled"):
        return np.zeros(x.shape, dtype=bool)
    fw, fh = lens.width / lens.cols, lens.height / lens.rows
    return near(x / fw, fw) | near(y / fh, fh)


def random_directions(n, seed=1):
    rng = np.random.default_rng(seed)
    d = rng.normal(size=(n, 3))
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    # the axes, the poles and the back pole exactly
    extra = np.array([[0, 0, 1], [0, 0, -1], [0, 1, 0], [0, -1, 0], [1, 0, 0], [-1, 0, 0]], dtype=float)
    return np.concatenate([d, extra])


@pytest.mark.parametrize("spec,size", CASES, ids=[c[0] for c in CASES])
def test_direction_pixel_direction(spec, size):
    lens = make_lens(spec, size)
    d = random_directions(20000)
    xy, ok = lens.dir_to_pixel(d)
    assert np.isfinite(xy).all()
    assert ok.sum() > 100
    inside = xy[ok]
    assert (inside >= 0).all() and (inside[:, 0] <= lens.width).all() and (inside[:, 1] <= lens.height).all()
    d2, valid = lens.pixel_to_dir(xy)
    assert valid[ok].all()
    err = angle(d2[ok], d[ok])
    # the back pole of a 360-degree fisheye comes back from the rim (the rim *is* -z) up to the
    # rounding of sin(pi): 1.2e-16 rad
    tol = direction_tolerance(lens, xy[ok])
    assert (err < tol).all(), (err.max(), d[ok][np.argmax(err - tol)])


@pytest.mark.parametrize("spec,size", [c for c in CASES if not c[0].startswith(("tiled", "cubemap"))],
                         ids=[c[0] for c in CASES if not c[0].startswith(("tiled", "cubemap"))])
@settings(max_examples=40, deadline=None)
@given(fx=st.floats(0.0, 1.0), fy=st.floats(0.0, 1.0))
def test_pixel_round_trip_property(spec, size, fx, fy):
    """Any pixel in the image, edges included (hypothesis explores 0, 1 and the odd floats)."""
    lens = make_lens(spec, size)
    xy = np.array([[fx * size[0], fy * size[1]]])
    d, valid = lens.pixel_to_dir(xy)
    assert np.isfinite(d).all()
    if not valid[0]:
        assert (d == 0).all()
    elif not excluded(lens, xy)[0]:
        back, ok = lens.dir_to_pixel(d)
        assert ok[0]
        if shared_pixels(lens, xy)[0]:
            assert angle(lens.pixel_to_dir(back)[0], d).max() < direction_tolerance(lens, xy)[0]
        else:
            assert np.abs(back - xy).max() < PX_TOL
