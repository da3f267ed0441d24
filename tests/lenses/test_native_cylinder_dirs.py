"""The cylinders', Pannini's and the little planet's compiled pixel -> direction (``cylinder_dirs``, ``pannini_dirs``,
``turned_fisheye_dirs``, ``src/native/lens_dirs.cpp``; their DirKernel, which ``Lens.pixel_to_dir`` and so the
warp's exact map run), against the models' own NumPy steps (their specification) on pixels drawn by hypothesis with
the extremes mixed in (the corners and edges, far outside, NaN and infinite pixels, fields of view near 0 and at 360
degrees, vfov 180), and against the inverse formulas of J. P. Snyder, *Map Projections - A Working Manual* (1987;
Mercator section 7, the equal-area cylinder section 10), of the stereographic fisheye and Sharpless et al.'s Pannini
(2010, eq. 1-2), transcribed here in float64.

Tolerances: the kernels run the NumPy steps' operations in the same order without fused multiply-adds, so validity
is the same bit for bit; the directions differ by the last bits of the sines and cosines of the longitude and of
Mercator's tanh and cosh, which the kernel takes from glibc's vector maths (each within 4 ulps) and NumPy from its
own loops (Pannini's arc tangent too), two of them multiplied: 8 ulps of a unit vector (2e-15). The little planet's
turn is an exact axis permutation: the fisheye kernel's 4 ulps (1e-15, as tests/lenses/test_native_pixel_dirs.py
holds it). Snyder's inverse reaches the direction through other functions (an arc tangent of an exponential, an arc
sine, then the sine and cosine of the latitude): within 1e-12 of a unit ray (a few ulps, times 1/cos of the latitude
where the arc sine nears the pole)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given

from lenslab.lenses import make_lens
from lenslab.lenses.core.native import unproject_kernel
from tests.lenses.test_native_lens_kernels import HYP, PIXELS

SPECS = [("cylindrical", (1024, 512)), ("cylindrical:fov=180,vfov=120", (4096, 2048)),
         ("cylindrical:fov=0.01", (64, 64)), ("cylindrical-equal-area", (4096, 1304)),
         ("cylindrical-equal-area:vfov=180", (4096, 2048)), ("cylindrical-equal-area:fov=359.99", (333, 4096)),
         ("mercator", (4096, 4096)), ("mercator:fov=200,vfov=150", (1024, 512)), ("mercator:fov=0.01", (64, 64)),
         ("mercator:vfov=179.999", (256, 256)),
         ("pannini", (800, 400)), ("pannini:fov=170,d=2,vcomp=0.5", (512, 512)), ("pannini:fov=100,d=0", (300, 700)),
         ("pannini:fov=0.01", (64, 64)), ("pannini:fov=239.9,d=0.5,vcomp=1", (800, 400)),
         ("little-planet", (4096, 4096)), ("little-planet:fov=359.9", (640, 400)), ("little-planet:fov=0.01", (64, 64))]


def numpy_dirs(lens):
    """``lens`` with its compiled pixel -> dir switched off: its NumPy steps run."""
    lens.dir_kernel = lambda: None
    return lens


@pytest.mark.parametrize("spec,size", SPECS)
@HYP
@given(xy=PIXELS)
def test_the_kernels_are_the_models_numpy_steps(spec, size, xy):
    lens = make_lens(spec, size)
    kern = lens.dir_kernel()
    assert kern is not None
    d, ok = unproject_kernel(kern, xy)
    want, want_ok = numpy_dirs(lens).pixel_to_dir(xy)
    np.testing.assert_array_equal(ok, want_ok)
    np.testing.assert_allclose(d, want, rtol=0, atol=1e-15 if spec.startswith("little") else 2e-15)
    assert np.all(d[~ok] == 0.0)


#: Snyder's inverse: the latitude of the height y on the unit sphere (Mercator eq. 7-4; equal-area, section 10,
#: standard parallel 0; the central cylinder: the ray through the axis)
SNYDER_LAT = {
    "mercator": lambda y: np.pi / 2.0 - 2.0 * np.arctan(np.exp(-y)),
    "cylindrical-equal-area": np.arcsin,
    "cylindrical": np.arctan,
}


@pytest.mark.parametrize("name,extra,size", [("mercator", "", (1024, 1024)), ("mercator", ":fov=200,vfov=150",
                                                                               (1024, 512)),
                                             ("cylindrical-equal-area", "", (1024, 326)),
                                             ("cylindrical-equal-area", ":fov=300,vfov=180", (1024, 512)),
                                             ("cylindrical", ":fov=180,vfov=120", (1024, 512))])
def test_cylinder_kernels_are_snyders_inverse(name, extra, size):
    """lambda = x / R about the image centre with R = W / fov (radians) (eq. 7-5), the latitude of the height
    (H/2 - y) / R, or with vfov of h(vfov/2) (H/2 - y) / (H/2); d = (cos phi sin lambda, sin phi,
    cos phi cos lambda)."""
    w, h = size
    lens = make_lens(name + extra, size)
    rng = np.random.default_rng(11)
    xy = np.stack([rng.uniform(0.0, w, 20000), rng.uniform(0.0, h, 20000)], -1)
    R = w / np.radians(lens.fov)
    lam = (xy[:, 0] - w / 2.0) / R
    if lens.vfov == 0:
        y = (h / 2.0 - xy[:, 1]) / R
    else:
        top = {"mercator": lambda p: np.arctanh(np.sin(p)), "cylindrical-equal-area": np.sin,
               "cylindrical": np.tan}[name](np.radians(lens.vfov) / 2.0)
        y = (h / 2.0 - xy[:, 1]) / (h / 2.0) * top
    phi = SNYDER_LAT[name](np.clip(y, -1.0, 1.0) if name == "cylindrical-equal-area" else y)
    want = np.stack([np.cos(phi) * np.sin(lam), np.sin(phi), np.cos(phi) * np.cos(lam)], -1)
    d, ok = unproject_kernel(lens.dir_kernel(), xy)
    inside = np.abs(y) <= 1.0 if name == "cylindrical-equal-area" else np.ones(len(y), bool)
    assert inside.sum() > 10000 and ok[inside].all() and not ok[~inside].any()
    np.testing.assert_allclose(d[inside], want[inside], rtol=0, atol=1e-12)


def test_little_planet_kernel_is_the_stereographic_fisheye_looking_down():
    """theta = 2 atan(r / (2 f)) from the lens axis -y with f = (W/2) / (2 tan(fov/4)), azimuth atan2 of the lens's
    (x, y) = (+x, +z): d = (sin(theta) cos(a), -cos(theta), sin(theta) sin(a))."""
    w = h = 1024
    rng = np.random.default_rng(12)
    xy = np.stack([rng.uniform(0.0, w, 20000), rng.uniform(0.0, h, 20000)], -1)
    lx, ly = xy[:, 0] - w / 2.0, h / 2.0 - xy[:, 1]
    r = np.hypot(lx, ly)
    f = (w / 2.0) / (2.0 * np.tan(np.radians(270.0) / 4.0))
    theta = 2.0 * np.arctan(r / (2.0 * f))
    a = np.arctan2(ly, lx)
    want = np.stack([np.sin(theta) * np.cos(a), -np.cos(theta), np.sin(theta) * np.sin(a)], -1)
    d, ok = unproject_kernel(make_lens("little-planet", (w, h)).dir_kernel(), xy)
    inside = r <= w / 2.0
    assert ok[inside].all() and not ok[r > w / 2.0 + 1e-6].any()
    np.testing.assert_allclose(d[inside], want[inside], rtol=0, atol=1e-12)


@pytest.mark.parametrize("fov,dist,size", [(150.0, 1.0, (1200, 600)), (170.0, 2.0, (1024, 1024)),
                                           (100.0, 0.0, (640, 480))])
def test_pannini_kernel_rays_land_where_sharpless_formula_puts_them(fov, dist, size):
    """Each ray's longitude phi and latitude theta, through Sharpless, Postle and German's eq. 1-2 (S = (d + 1) /
    (d + cos phi), x = S sin phi, y = S tan theta, scaled so that fov/2 is at the side edges: pixel x = W/2 (1 + x /
    x_F), y = H/2 - W/2 y / x_F, x_F = S(fov/2) sin(fov/2)), land on the pixel the ray came from: within 1e-9 px
    (a few ulps of the ray, times at most 1e3 px per unit)."""
    w, h = size
    rng = np.random.default_rng(16)
    xy = np.stack([rng.uniform(0.0, w, 20000), rng.uniform(0.0, h, 20000)], -1)
    d, ok = unproject_kernel(make_lens(f"pannini:fov={fov:g},d={dist:g}", size).dir_kernel(), xy)
    assert ok.all()
    phi = np.arctan2(d[:, 0], d[:, 2])
    theta = np.arctan2(d[:, 1], np.hypot(d[:, 0], d[:, 2]))
    S = (dist + 1.0) / (dist + np.cos(phi))
    F = np.radians(fov) / 2.0
    x_f = (dist + 1.0) / (dist + np.cos(F)) * np.sin(F)
    back = np.stack([w / 2.0 * (1.0 + S * np.sin(phi) / x_f), h / 2.0 - w / 2.0 * S * np.tan(theta) / x_f], -1)
    np.testing.assert_allclose(back, xy, rtol=0, atol=1e-9)
