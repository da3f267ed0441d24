"""The fisheye's and the perspective's compiled pixel -> direction (``fisheye_dirs``, ``perspective_dirs``,
``src/native/lens_dirs.cpp``, which ``Lens.pixel_to_dir`` and so the warp's exact map run) against the fisheye's
NumPy reference (:func:`lenslab.lenses.formulas.reference.fisheye_dirs`), against the models' own NumPy steps,
against OpenCV (``cv2.fisheye.undistortPoints``, equidistant; ``cv2.undistortPoints``, pinhole) and against the
mappings of Kannala and Brandt (2006, table 1) transcribed here in float64; on pixels drawn by hypothesis with the
extremes mixed in: the rim, the centre, far outside, NaN and infinite pixels, fields of view near 0 and at 360
degrees (the rim is then the back pole), off-centre and full-frame circles.

Tolerances: the kernels run the NumPy steps' operations in the same order without fused multiply-adds, so
validity is the same bit for bit, the perspective's directions too, and the fisheye's differ at most by the last
bits of the sine and cosine (equidistant), which the kernel takes from glibc's vector maths (4 ulps at most) and
NumPy from its own loops: 4 ulps of a unit vector (1e-15). The outside oracles compute the direction another way
(an angle, then its sine and cosine; OpenCV's iterative undistortion to 1e-12 and its tangent plane): 1e-9 of a
unit ray (4e-6 px at 4096 px).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lenslab.lenses import make_lens
from lenslab.lenses.core.base import Lens
from lenslab.lenses.formulas import reference
from lenslab.lenses.projections.fisheye import Fisheye

NAN, INF = math.nan, math.inf
ULPS = 1e-15  # 4 ulps of a unit vector (see the module docstring)
ORACLE = 1e-9
HYP = settings(max_examples=60, deadline=None)

MAPPINGS = {"equidistant": 360.0, "equisolid": 360.0, "stereographic": 359.0, "orthographic": 180.0}


@st.composite
def fisheyes(draw):
    mapping = draw(st.sampled_from(sorted(MAPPINGS)))
    hi = MAPPINGS[mapping]
    fov = draw(st.one_of(st.sampled_from([1e-6, 0.01, hi, hi - 1e-9, 180.0]), st.floats(1e-6, hi)))
    w = draw(st.integers(1, 4096))
    h = draw(st.one_of(st.just(w), st.integers(1, 4096)))
    kind = draw(st.sampled_from(["fov", "fov", "vfov", "dfov"]))
    text = f"fisheye:mapping={mapping}"
    if kind == "fov":
        text += f",fov={fov!r}"
    else:
        text += f",{kind}={min(fov, 179.0)!r}"
    if draw(st.booleans()):
        text += f",cx={draw(st.floats(-0.5, 0.5))!r},cy={draw(st.floats(-0.5, 0.5))!r}"
    return make_lens(text, (w, h))


@st.composite
def pixels(draw, lens):
    w, h = lens.width, lens.height
    cx, cy = 0.5 * w * (1.0 + lens.cx), 0.5 * h - 0.5 * w * lens.cy
    rim = [(cx + 0.5 * w * lens.r_ref * c, cy + 0.5 * w * lens.r_ref * s) for c, s in ((1, 0), (-1, 0), (0, 1),
                                                                                       (0, -1), (0.6, 0.8))]
    extreme = [(cx, cy), (0.0, 0.0), (w, h), (w, 0.5 * h), (-1e6, 3.0), (1e300, 1.0), (1e155, 1e155), (NAN, 5.0),
               (3.0, INF), (-INF, -INF)] + rim
    px = st.floats(-0.2 * w, 1.2 * w, allow_nan=False)
    py = st.floats(-0.2 * h, 1.2 * h, allow_nan=False)
    rows = draw(st.lists(st.one_of(st.sampled_from(extreme), st.tuples(px, py)), min_size=1, max_size=64))
    return np.array(rows, dtype=np.float64)


def _numpy_steps(lens, xy):
    return Lens._uv_pixel_to_dir(lens, xy)


@HYP
@given(st.data())
def test_kernel_matches_its_reference_and_the_models_numpy_steps(data):
    lens = data.draw(fisheyes())
    xy = data.draw(pixels(lens))
    kern = lens.dir_kernel()
    assert kern is not None
    d, ok = lens.pixel_to_dir(xy)
    assert d.dtype == np.float64 and ok.dtype == np.bool_
    for want, want_ok in (_numpy_steps(lens, xy), reference.fisheye_dirs(xy, kern.params)):
        np.testing.assert_array_equal(ok, want_ok)
        np.testing.assert_allclose(d, want, rtol=0, atol=ULPS)
    assert np.all(d[~ok] == 0.0) and np.all(np.isfinite(d))
    np.testing.assert_allclose(np.linalg.norm(d[ok], axis=-1), 1.0, rtol=0, atol=1e-15)
    assert not ok[~np.isfinite(xy).all(-1)].any()


def test_rim_of_a_360_degree_fisheye_is_the_back_pole_and_fov_near_0_stays_on_the_axis():
    for mapping in ("equidistant", "equisolid"):
        lens = make_lens(f"fisheye:fov=360,mapping={mapping}", (4096, 4096))
        d, ok = lens.pixel_to_dir(np.array([[4096.0, 2048.0], [2048.0, 0.0], [4096.0 + 1e-6, 2048.0]]))
        assert ok.tolist() == [True, True, False]
        np.testing.assert_allclose(d[:2], [[0, 0, -1], [0, 0, -1]], rtol=0, atol=1e-15)
    lens = make_lens("fisheye:fov=1e-06", (4096, 4096))
    d, ok = lens.pixel_to_dir(np.array([[4096.0, 2048.0], [2048.0, 2048.0]]))
    assert ok.all()
    half = math.radians(1e-6) / 2  # the rim is fov/2 from the axis: (sin, 0, cos) of it
    np.testing.assert_allclose(d, [[math.sin(half), 0.0, math.cos(half)], [0.0, 0.0, 1.0]], rtol=0, atol=ULPS)


def test_the_rim_of_a_360_degree_equisolid_fisheye_is_the_unit_back_pole_whatever_its_rounding():
    # 1 x 9: the plane scale's square rounds s^2 / 4 to 1 + 2 ulps at the rim, where 1 - s^2 / 2 fell below -1
    # (a direction of length 1 + 1.8e-15); the back pole is (0, 0, -1) exactly, in NumPy and in the kernel
    lens = make_lens("fisheye:fov=360,mapping=equisolid", (1, 9))
    xy = np.array([[0.5, 5.0], [0.5, 4.0], [0.5, 4.5]])
    d, ok = lens.pixel_to_dir(xy)
    want, want_ok = _numpy_steps(lens, xy)
    assert ok.all() and want_ok.all()
    np.testing.assert_array_equal(np.abs(d[:2]), [[0.0, 0.0, 1.0], [0.0, 0.0, 1.0]])
    np.testing.assert_array_equal(d[:2, 2], [-1.0, -1.0])
    np.testing.assert_array_equal(d, want)
    np.testing.assert_array_equal(d[2], [0.0, 0.0, 1.0])  # the centre: the axis


def test_equidistant_matches_opencv_fisheye_undistort_points():
    cv2 = pytest.importorskip("cv2")
    w = h = 1024
    lens = make_lens("fisheye:fov=180", (w, h))
    f = (w / 2) / (math.pi / 2)  # r = f theta reaches the edge at 90 degrees
    rng = np.random.default_rng(7)
    r = 0.98 * (w / 2) * np.sqrt(rng.uniform(0, 1, 500))  # inside 88 degrees: a finite tangent plane
    a = rng.uniform(-np.pi, np.pi, 500)
    xy = np.stack([w / 2 + r * np.cos(a), h / 2 + r * np.sin(a)], -1)
    K = np.array([[f, 0, w / 2 - 0.5], [0, f, h / 2 - 0.5], [0, 0, 1]])  # OpenCV's pixel centres at integers
    und = cv2.fisheye.undistortPoints((xy - 0.5).reshape(-1, 1, 2), K, np.zeros(4),
                                      criteria=(cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS, 50, 1e-12))
    X, Y = und[:, 0, 0], und[:, 0, 1]
    want = np.stack([X, -Y, np.ones_like(X)], -1)  # OpenCV's y points down, lenslab's up
    want /= np.linalg.norm(want, axis=-1, keepdims=True)
    d, ok = lens.pixel_to_dir(xy)
    assert ok.all()
    np.testing.assert_allclose(d, want, rtol=0, atol=ORACLE)


@pytest.mark.parametrize("mapping", ["equidistant", "equisolid", "stereographic", "orthographic"])
def test_mappings_match_kannala_brandt_formulas_transcribed(mapping):
    """r = f theta, 2 f sin(theta/2), 2 f tan(theta/2), f sin(theta), f set so that r = W/2 at fov/2."""
    w, h, fov = 2000, 1500, {"orthographic": 170.0}.get(mapping, 200.0)
    lens = make_lens(f"fisheye:fov={fov:g},mapping={mapping}", (w, h))
    g = {"equidistant": (lambda t: t, lambda s: s),
         "equisolid": (lambda t: 2 * np.sin(t / 2), lambda s: 2 * np.arcsin(s / 2)),
         "stereographic": (lambda t: 2 * np.tan(t / 2), lambda s: 2 * np.arctan(s / 2)),
         "orthographic": (np.sin, np.arcsin)}[mapping]
    f = (w / 2) / g[0](math.radians(fov) / 2)
    rng = np.random.default_rng(3)
    xy = np.stack([rng.uniform(0, w, 2000), rng.uniform(0, h, 2000)], -1)
    dx, dy = xy[:, 0] - w / 2, h / 2 - xy[:, 1]
    r = np.hypot(dx, dy)
    inside = r <= w / 2
    theta = g[1](r[inside] / f)
    phi = np.arctan2(dy[inside], dx[inside])
    want = np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], -1)
    d, ok = lens.pixel_to_dir(xy)
    np.testing.assert_array_equal(ok, inside)
    np.testing.assert_allclose(d[inside], want, rtol=0, atol=ORACLE)


def test_a_model_that_changes_a_step_has_no_kernel():
    class Shifted(Fisheye):
        name = ""

        def uv_to_dir(self, uv):
            return super().uv_to_dir(uv + 0.01)

    lens = Shifted(64, 64, fov=180.0)
    assert lens.dir_kernel() is None
    xy = np.array([[32.0, 32.0]])
    np.testing.assert_array_equal(lens.pixel_to_dir(xy)[0], Fisheye.uv_to_dir(lens, np.array([[0.01, 0.01]]))[0])


@st.composite
def perspectives(draw):
    kind = draw(st.sampled_from(["fov", "vfov", "dfov"]))
    angle = draw(st.one_of(st.sampled_from([1e-6, 0.01, 90.0, 179.0, 179.999]), st.floats(1e-6, 179.999)))
    w, h = draw(st.integers(1, 4096)), draw(st.integers(1, 4096))
    return make_lens(f"perspective:{kind}={angle!r}", (w, h))


@HYP
@given(st.data())
def test_perspective_kernel_gives_its_numpy_steps_bits(data):
    """Only multiplies, adds, a square root and a division, in the NumPy steps' order: the same bits."""
    lens = data.draw(perspectives())
    xy = data.draw(pixels(make_lens("fisheye", (lens.width, lens.height))))
    assert lens.dir_kernel() is not None
    d, ok = lens.pixel_to_dir(xy)
    want, want_ok = _numpy_steps(lens, xy)
    np.testing.assert_array_equal(ok, want_ok)
    np.testing.assert_array_equal(d, want)
    assert ok[np.isfinite(xy).all(-1) & (np.abs(xy) < 1e100).all(-1)].all()  # every finite pixel has a ray
    assert not ok[~np.isfinite(xy).all(-1)].any() and np.all(d[~ok] == 0.0)


def test_perspective_matches_opencv_undistort_points():
    cv2 = pytest.importorskip("cv2")
    w, h = 1920, 1080
    lens = make_lens("perspective:fov=100", (w, h))
    f = (w / 2) / math.tan(math.radians(50))  # the image's half width at 50 degrees
    rng = np.random.default_rng(5)
    xy = np.stack([rng.uniform(-200, w + 200, 500), rng.uniform(-200, h + 200, 500)], -1)
    K = np.array([[f, 0, w / 2 - 0.5], [0, f, h / 2 - 0.5], [0, 0, 1]])  # OpenCV's pixel centres at integers
    und = cv2.undistortPoints((xy - 0.5).reshape(-1, 1, 2), K, np.zeros(5))
    want = np.stack([und[:, 0, 0], -und[:, 0, 1], np.ones(len(xy))], -1)  # OpenCV's y points down
    want /= np.linalg.norm(want, axis=-1, keepdims=True)
    d, ok = lens.pixel_to_dir(xy)
    assert ok.all()
    np.testing.assert_allclose(d, want, rtol=0, atol=ORACLE)
