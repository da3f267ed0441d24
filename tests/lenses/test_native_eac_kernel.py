"""The equi-angular cube map's compiled dir -> pixel (``eac_pixels`` in ``lenslab.cxx_kernels``): against ffmpeg
v360's ``eac`` convention transcribed here in float64, and against the model's NumPy steps
(``EquiAngularCubemap._dir_to_pixel``) on directions drawn by hypothesis with the cube's edges, corners, axes, huge
and tiny lengths, zero, NaN and infinite directions mixed in. The v360 pixel pinned on the model and a subclass that
changes a step are checked beside the cube map's (``test_native_cubemap_kernel.py``).

v360's ``eac_to_xyz`` (libavfilter/vf_v360.c) reads pixel ``i`` at ``(i + 0.5) / width``, the continuous position of
its centre in lenslab's convention too; its frame has x right, y up and looks along -z (its ``flat_to_xyz`` gives
the pinhole's centre ray ``(0, 0, -1)``), so a lenslab direction is v360's with z negated.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lenslab.lenses import make_lens
from lenslab.lenses.core.native import lens_kernels, project_kernel
from lenslab.lenses.panoramas.eac import EquiAngularCubemap
from lenslab.warp.maps import COMPILED_PROJECT_MIN, project
from tests.lenses.test_native_cubemap_kernel import DIRS, EDGES, INVALID

EPS = np.finfo(np.float64).eps
LENSES = [("eac", (600, 400)), ("eac:pad=2", (600, 400)), ("eac", (1536, 1024)), ("eac:pad=2", (8192, 5462)),
          ("eac:pad=3.5", (1001, 667))]


def v360_eac_to_xyz(x: float, y: float, width: int, height: int, pad: float) -> tuple[float, float, float]:
    """v360's ``eac_to_xyz`` at the continuous position (x, y) inside a face, in float64 (v360 pads with 2)."""
    u_pad, v_pad = pad / width, pad / height
    uf = 3.0 * (x / width - u_pad) / (1.0 - 2.0 * u_pad)
    u_face = math.floor(uf)
    uf = uf - u_face - 0.5
    vf = y / height
    v_face = math.floor(vf * 2.0)
    vf = (vf - v_pad - 0.5 * v_face) / (0.5 - 2.0 * v_pad) - 0.5
    uf, vf = math.tan(math.pi / 2 * uf), math.tan(math.pi / 2 * vf)
    face = u_face + 3 * v_face  # top row: left, front, right; bottom row: down, back, up
    vec = {0: (-1.0, -vf, -uf), 1: (uf, -vf, -1.0), 2: (1.0, -vf, uf),
           3: (-vf, -1.0, uf), 4: (-vf, uf, 1.0), 5: (-vf, 1.0, -uf)}[face]
    n = math.sqrt(sum(c * c for c in vec))
    return vec[0] / n, vec[1] / n, -vec[2] / n  # into lenslab's frame: z forward


@pytest.mark.parametrize("spec,size", LENSES)
def test_pixels_of_v360_eac_directions(spec, size):
    """Positions inside each of the six faces (away from the face edges, where a direction belongs to two faces):
    v360's direction of each comes back to it. Tolerance 1e-9 px: tan then atan in float64 lose a few ulps of the
    face fraction, about 1e-12 px on these faces."""
    w, h = size
    lens = make_lens(spec, size)
    pad = lens.pad
    fw, fh = (w - 2 * pad) / 3.0, h / 2.0 - 2 * pad
    rng = np.random.default_rng(7)
    pts = []
    for face in range(6):
        col, row = face % 3, face // 3
        for fx, fy in rng.uniform(0.002, 0.998, size=(40, 2)):
            pts.append((pad + (col + fx) * fw, pad + row * h / 2.0 + fy * fh))
    pts.append((pad + 1.5 * fw, pad + 0.5 * fh))  # the front face's centre: straight ahead
    d = np.array([v360_eac_to_xyz(x, y, w, h, pad) for x, y in pts])
    np.testing.assert_allclose(d[-1], (0.0, 0.0, 1.0), atol=1e-15)
    xy, ok = project_kernel(lens.pixel_kernel(), d)
    assert ok.all()
    np.testing.assert_allclose(xy, np.array(pts), rtol=0, atol=1e-9)


def numpy_steps(lens, d):
    with np.errstate(all="ignore"):
        return EquiAngularCubemap._dir_to_pixel(lens, d.copy())


def close_to_steps(lens, xy, ok, d):
    """The kernel and the NumPy steps: the same validity, positions within 16 ulps of the image's larger side (their
    arc tangents, glibc's and NumPy's, differ by a few ulps, and NumPy rounds the quotient d.A / t first; the layout
    adds three roundings of a position below that side)."""
    want, want_ok = numpy_steps(lens, d)
    np.testing.assert_array_equal(ok, want_ok)
    np.testing.assert_allclose(xy, want, rtol=0, atol=16 * EPS * max(lens.width, lens.height))
    assert (xy[~ok] == 0).all()


@pytest.mark.parametrize("spec,size", LENSES)
@settings(max_examples=60, deadline=None)
@given(d=DIRS)
def test_kernel_follows_the_numpy_steps(spec, size, d):
    lens = make_lens(spec, size)
    kern = lens.pixel_kernel()
    assert kern is not None and kern.fn.__name__ == "eac_pixels"
    xy, ok = project_kernel(kern, d)
    close_to_steps(lens, xy, ok, d)
    # the model's dir_to_pixel and the warp's project run the same kernel, at any size, with the same values
    # wherever a direction falls in a call (four at a time, a short block padded)
    for got_xy, got_ok in (lens.dir_to_pixel(d), project(lens, d),
                           project(lens, np.repeat(d, COMPILED_PROJECT_MIN + 1, axis=0))):
        n = len(got_ok) // len(d)
        np.testing.assert_array_equal(got_ok, np.repeat(ok, n))
        np.testing.assert_array_equal(got_xy, np.repeat(xy, n, axis=0))


@pytest.mark.parametrize("spec,size", LENSES)
def test_edges_corners_and_invalid_directions(spec, size):
    lens = make_lens(spec, size)
    d = np.array(EDGES + INVALID, dtype=np.float64)
    xy, ok = lens.dir_to_pixel(d)
    close_to_steps(lens, xy, ok, d)
    assert ok[:len(EDGES)].all() and not ok[len(EDGES):].any()


@pytest.mark.parametrize("bad", ["short", "axis"])
def test_the_binding_refuses_parameters_it_cannot_use(bad):
    p = make_lens("eac", (600, 400)).pixel_kernel().params.copy()
    if bad == "short":
        p = p[:-1]
    else:
        p[7 + 2] = 3.0  # a component index past z
    d = np.zeros((1, 3))
    with pytest.raises(ValueError, match="eac"):
        lens_kernels().eac_pixels(d, p, np.empty((1, 2)), np.empty(1, bool))


# -- pixel -> direction (eac_dirs, the model's DirKernel) ------------------------------------------------------------

@pytest.mark.parametrize("spec,size", LENSES)
def test_directions_of_pixels_are_v360s(spec, size):
    """v360's direction of positions inside each face (its faces' edges and the pad excluded: v360 stretches the pad
    its own way); tolerance 8 ulps of a unit vector (both take two tangents in float64, lenslab's as sine over cosine)."""
    w, h = size
    lens = make_lens(spec, size)
    pad = lens.pad
    fw, fh = (w - 2 * pad) / 3.0, h / 2.0 - 2 * pad
    rng = np.random.default_rng(11)
    pts = np.array([(pad + (face % 3 + fx) * fw, pad + (face // 3) * h / 2.0 + fy * fh)
                    for face in range(6) for fx, fy in rng.uniform(0.001, 0.999, size=(40, 2))])
    want = np.array([v360_eac_to_xyz(x, y, w, h, pad) for x, y in pts])
    d, ok = lens.pixel_to_dir(pts)
    assert ok.all() and lens.dir_kernel() is not None
    np.testing.assert_allclose(d, want, rtol=0, atol=8 * EPS)


coord_px = st.one_of(st.floats(-3.0, 1.01, allow_nan=False).map(lambda f: f * 1024.0),
                     st.sampled_from([0.0, -0.0, 1e-300, 2.0, 3.5, 200.0, 341.0 + 1 / 3, 512.0, 1024.0, math.nan,
                                      math.inf, -math.inf, 1e300]))
PIXELS = st.lists(st.tuples(coord_px, coord_px), min_size=1, max_size=64).map(lambda r: np.array(r, dtype=np.float64))


@pytest.mark.parametrize("spec,size", LENSES)
@settings(max_examples=60, deadline=None)
@given(xy=PIXELS)
def test_dir_kernel_follows_the_numpy_steps(spec, size, xy):
    """Pixels anywhere (the pad, the faces' borders, the image's edges and beyond, NaN and infinities): the same
    validity as the NumPy steps, unit directions within 8 ulps (their tangents: NumPy's against sine over cosine),
    zero where there is no ray; the same values wherever a pixel falls in a call."""
    lens = make_lens(spec, size)
    xy = xy * np.array([size[0], size[1]]) / 1024.0
    d, ok = lens.pixel_to_dir(xy)
    with np.errstate(all="ignore"):
        want, want_ok = EquiAngularCubemap._pixel_to_dir(lens, xy.copy())
    np.testing.assert_array_equal(ok, want_ok)
    np.testing.assert_allclose(d, want, rtol=0, atol=8 * EPS)
    assert (d[~ok] == 0).all()
    many, many_ok = lens.pixel_to_dir(np.repeat(xy, 5, axis=0))
    np.testing.assert_array_equal(many, np.repeat(d, 5, axis=0))
    np.testing.assert_array_equal(many_ok, np.repeat(ok, 5))


def test_a_model_that_changes_a_pixel_step_keeps_its_numpy_steps():
    class Turned(EquiAngularCubemap):
        name = "eac-turned-test"

        def _pixel_to_dir(self, xy):
            d, ok = super()._pixel_to_dir(xy)
            return -d, ok

    lens = Turned(width=600, height=400)
    assert lens.dir_kernel() is None
    d, ok = lens.pixel_to_dir([[300.0, 100.0]])  # the front face's centre, turned back
    np.testing.assert_allclose(d, [[0.0, 0.0, -1.0]], atol=1e-15)


def test_the_dir_binding_refuses_a_wrong_parameter_count():
    p = make_lens("eac", (600, 400)).dir_kernel().params[:-1]
    with pytest.raises(ValueError, match="parameters"):
        lens_kernels().eac_dirs(np.zeros((1, 2)), p, np.empty((1, 3)), np.empty(1, bool))
