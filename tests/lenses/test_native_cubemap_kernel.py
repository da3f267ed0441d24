"""The cube map's compiled dir -> pixel (``cubemap_pixels`` in ``lenslab.cxx_kernels``) against the model's NumPy
steps (``Cubemap._dir_to_pixel``), bit for bit, on every layout and several face orders.

The kernel does the NumPy operations in the same order (built without fused multiply-adds) and has no
transcendental function: a major component, a multiplication by a sign, one division, then additions and
multiplications by the face size, a minimum and a clip. IEEE-754 rounds each of these the same way in C++ and in
NumPy, so the results are required to be equal, not close. Directions are drawn by hypothesis with the hard cases
mixed in: the face edges and the cube's corners (two or three components of equal size, where the major axis is
decided by the first-on-ties rule), the axes, signed zeros, huge and tiny lengths, zero, NaN and infinite
directions (invalid).
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lenslab.lenses import make_lens
from lenslab.lenses.core.native import project_kernel
from lenslab.lenses.panoramas.cubemap import BORDER_NUDGE, Cubemap
from lenslab.lenses.panoramas.eac import EquiAngularCubemap
from lenslab.warp.maps import COMPILED_PROJECT_MIN, project

NAN, INF = math.nan, math.inf
SIGNS = (1.0, -1.0)
#: the cube's 8 corners, its 12 edges' midpoints and its 6 axes, with both zeros
EDGES = ([(sx, sy, sz) for sx, sy, sz in itertools.product(SIGNS, SIGNS, SIGNS)]
         + [p for sa, sb in itertools.product(SIGNS, SIGNS)
            for p in ((sa, sb, 0.0), (sa, 0.0, sb), (0.0, sa, sb), (sa, sb, -0.0), (-0.0, sa, sb))]
         + [(1.0, 0.0, 0.0), (-1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, -1.0, 0.0), (0.0, 0.0, 1.0),
            (0.0, 0.0, -1.0), (-0.0, -0.0, -1.0), (-0.0, 1.0, -0.0)])
INVALID = [(0.0, 0.0, 0.0), (-0.0, -0.0, -0.0), (NAN, 0.0, 1.0), (1.0, NAN, 0.0), (0.0, INF, 1.0),
           (-INF, 0.0, 0.0), (INF, INF, INF), (NAN, NAN, NAN), (1.0, 2.0, -INF)]
coord = st.floats(-1.0, 1.0, allow_nan=False, allow_infinity=False)
scale = st.sampled_from([1.0, 1e-300, 3e-12, 0.7, 1e12, 1e300, 5e-324])


@st.composite
def on_an_edge(draw):
    """A direction whose two or three largest components are equal in size (a face edge or a corner)."""
    a = draw(st.floats(1e-3, 1.0))
    b = draw(st.floats(-1.0, 1.0).map(lambda v: v * a))
    comps = [draw(st.sampled_from(SIGNS)) * a, draw(st.sampled_from(SIGNS)) * a, b]
    return tuple(draw(st.permutations(comps)))


ROW = st.one_of(st.sampled_from(EDGES + INVALID), on_an_edge(), st.tuples(coord, coord, coord))
DIRS = st.lists(st.tuples(ROW, scale), min_size=1, max_size=64).map(
    lambda rows: np.array([[c * s for c in r] for r, s in rows], dtype=np.float64))

LENSES = [("cubemap:layout=3x2", (600, 400)), ("cubemap:layout=3x2,order=fbrlud", (1536, 1024)),
          ("cubemap:layout=6x1", (1200, 200)), ("cubemap:layout=6x1,order=udfblr", (6000, 1000)),
          ("cubemap:layout=1x6", (333, 1998)), ("cubemap:layout=1x6,order=bfdulr", (100, 600)),
          ("cubemap:layout=4x3", (800, 600)), ("cubemap:layout=4x3,order=rludfb", (1000, 750)),
          ("cubemap:layout=4x3,order=dbrflu", (8192, 6144)),
          ("cubemap:layout=3x2", (1001, 667))]  # faces of a fractional size


def numpy_steps(lens, d):
    with np.errstate(all="ignore"):
        return Cubemap._dir_to_pixel(lens, d.copy())


@pytest.mark.parametrize("spec,size", LENSES)
@settings(max_examples=60, deadline=None)
@given(d=DIRS)
def test_kernel_is_the_numpy_steps_bit_for_bit(spec, size, d):
    lens = make_lens(spec, size)
    kern = lens.pixel_kernel()
    assert kern is not None and kern.fn.__name__ == "cubemap_pixels"
    want, want_ok = numpy_steps(lens, d)
    xy, ok = project_kernel(kern, d)
    np.testing.assert_array_equal(ok, want_ok)
    np.testing.assert_array_equal(xy, want)  # equal, signed zeros aside (assert_array_equal takes 0 == -0)
    assert not np.signbit(xy).any()
    # the model's dir_to_pixel and the warp's project run the same kernel, at any size
    for got in (lens.dir_to_pixel(d), project(lens, d), project(lens, np.repeat(d, COMPILED_PROJECT_MIN, axis=0))):
        got_xy, got_ok = got
        n = len(got_ok) // len(d)  # each direction repeated n times
        np.testing.assert_array_equal(got_ok, np.repeat(want_ok, n))
        np.testing.assert_array_equal(got_xy, np.repeat(want, n, axis=0))


@pytest.mark.parametrize("spec,size", LENSES)
def test_edges_corners_and_invalid_directions(spec, size):
    lens = make_lens(spec, size)
    d = np.array(EDGES + INVALID, dtype=np.float64)
    want, want_ok = numpy_steps(lens, d)
    xy, ok = lens.dir_to_pixel(d)
    np.testing.assert_array_equal(ok, want_ok)
    np.testing.assert_array_equal(xy, want)
    assert ok[:len(EDGES)].all() and not ok[len(EDGES):].any()
    assert (xy[len(EDGES):] == 0).all()


def test_corners_pinned_from_the_face_formulas():
    """c3x2 (rludfb) at 600 x 400 (200 px faces), from the faces' formulas transcribed here: the right face
    d = (1, -vf, -uf) holds the corners with x largest (ties go to x), (1, 1, 1) at its top left (uf = vf = -1) and
    (1, -1, -1) at its bottom right, kept BORDER_NUDGE px inside; the front face d = (uf, -vf, 1) has (0, 0, 1) at
    its centre, the middle of the bottom row's second face; the up face d = (uf, 1, vf) has (0, 1, 1) (a tie of y
    and z, to y) on its bottom edge's middle, kept inside; (-2, 2, 0) is on the left face's top edge."""
    lens = make_lens("cubemap:layout=3x2", (600, 400))
    d = np.array([(1.0, 1.0, 1.0), (1.0, -1.0, -1.0), (0.0, 0.0, 1.0), (0.0, 1.0, 1.0), (-2.0, 2.0, 0.0)])
    xy, ok = lens.dir_to_pixel(d)
    assert ok.all()
    want = [(0.0, 0.0), (200.0 - BORDER_NUDGE, 200.0 - BORDER_NUDGE), (300.0, 300.0),
            (500.0, 200.0 - BORDER_NUDGE),
            (300.0, 0.0)]  # a tie of x and y, to x: the left face d = (-1, -vf, uf) at uf = 0, vf = -1
    np.testing.assert_array_equal(xy, np.array(want))


@pytest.mark.parametrize("model", [Cubemap, EquiAngularCubemap])
def test_reference_points_through_the_kernel(model):
    """The ffmpeg v360 pixels pinned on each cube map (its reference points) come back through its kernel, within each
    point's stated tolerance (the precision of its source)."""
    for ref in model.reference_points:
        lens = make_lens(ref.spec, ref.size)
        xy, ok = project_kernel(lens.pixel_kernel(), np.array([ref.direction], dtype=np.float64))
        assert ok.all()
        np.testing.assert_allclose(xy[0], ref.pixel, rtol=0, atol=ref.tolerance)


@pytest.mark.parametrize("model,want", [(Cubemap, [150.0, 150.0]), (EquiAngularCubemap, [150.0, 50.0])])
def test_a_model_that_changes_a_step_keeps_its_numpy_steps(model, want):
    class Shifted(model):
        name = f"{model.name}-shifted-test"

        def _dir_to_pixel(self, d):
            xy, ok = super()._dir_to_pixel(d)
            return xy * 0.5, ok

    lens = Shifted(width=600, height=400)
    assert lens.pixel_kernel() is None
    xy, ok = lens.dir_to_pixel([[0.0, 0.0, 1.0]])
    np.testing.assert_array_equal(xy, [want])
