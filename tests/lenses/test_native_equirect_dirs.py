"""The equirect's compiled pixel -> direction (``equirect_dirs``, ``src/native/lens_dirs.cpp``; its DirKernel, which
``Equirect.pixel_to_dir`` and so the warp's exact map and map lattice run when a panorama is the output) against the
model's own NumPy steps (``Equirect._pixel_to_dir``, its reference) on pixels drawn by hypothesis with the extremes
mixed in (corners, the poles' rows, the seam's columns, far outside, NaN and infinite pixels), and against the
latitude/longitude definition of ffmpeg's v360 ``equirect`` (``phi = (2x/W - 1) pi``, ``theta = (1 - 2y/H) pi/2``,
``d = (cos theta sin phi, sin theta, cos theta cos phi)``; a range's longitude and latitude linear between its
edges) transcribed here in float64 with Python's ``math`` (the C library's sine and cosine, not NumPy's loops).

Tolerances: the kernel runs the NumPy steps' operations in the same order without fused multiply-adds, so validity
is the same bit for bit and the exact poles are exact; the directions differ by the last bits of the sines and
cosines, which the kernel takes from glibc's vector maths (4 ulps at most) and NumPy from its own loops, two of them
multiplied: 8 ulps of a unit vector (2e-15), as tests/lenses/test_native_cylinder_dirs.py holds the cylinders.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given

from lenslab.lenses import make_lens
from lenslab.lenses.core.native import unproject_kernel
from lenslab.lenses.projections.equirect import Equirect
from tests.lenses.test_native_lens_kernels import HYP, PIXELS

SPECS = [("equirect", (4096, 2048)), ("equirect", (3540, 1770)), ("equirect", (7, 3)), ("equirect", (4096, 4096)),
         ("equirect:lon_min=-90,lon_max=120,lat_min=-30,lat_max=60", (4096, 3000)),
         ("equirect:lat_min=-45,lat_max=90", (1000, 300)), ("equirect:lon_min=-0.01,lon_max=0.01", (64, 64))]
ULPS = 2e-15  # see the module docstring


@pytest.mark.parametrize("spec,size", SPECS)
@HYP
@given(xy=PIXELS)
def test_the_kernel_is_the_models_numpy_steps(spec, size, xy):
    lens = make_lens(spec, size)
    w, h = size
    xy = np.concatenate([xy, [[0.0, 0.0], [w, h], [0.5 * w, 0.0], [0.5, h], [w, 0.5], [0.0, h + 1e-9],
                              [-1e-300, 1.0], [w * (1 + 1e-16), 1.0]]])
    kern = lens.dir_kernel()
    assert kern is not None
    d, ok = unproject_kernel(kern, xy)
    with np.errstate(all="ignore"):
        want, want_ok = lens._pixel_to_dir(xy.copy())
    np.testing.assert_array_equal(ok, want_ok)
    np.testing.assert_allclose(d, want, rtol=0, atol=ULPS)
    assert np.all(d[~ok] == 0.0)
    # the public method runs the kernel: its bits, whatever the call's length
    got, got_ok = lens.pixel_to_dir(xy)
    np.testing.assert_array_equal(got, d)
    np.testing.assert_array_equal(got_ok, ok)


def v360_dir(x, y, w, h, lon=(-180.0, 180.0), lat=(-90.0, 90.0)):
    """The direction of pixel position (x, y) of a w x h equirect spanning ``lon`` and ``lat`` (degrees)."""
    phi = math.radians(lon[0] + x / w * (lon[1] - lon[0]))
    theta = math.radians(lat[1] - y / h * (lat[1] - lat[0]))
    return (math.cos(theta) * math.sin(phi), math.sin(theta), math.cos(theta) * math.cos(phi))


@pytest.mark.parametrize("spec,size,lon,lat", [
    ("equirect", (3540, 1770), (-180.0, 180.0), (-90.0, 90.0)),
    ("equirect", (800, 400), (-180.0, 180.0), (-90.0, 90.0)),
    ("equirect:lon_min=-90,lon_max=120,lat_min=-30,lat_max=60", (4096, 3000), (-90.0, 120.0), (-30.0, 60.0))])
def test_the_kernel_is_the_latitude_longitude_definition(spec, size, lon, lat):
    w, h = size
    rng = np.random.default_rng(7)
    xy = np.stack([rng.uniform(0.0, w, 5000), rng.uniform(0.0, h, 5000)], -1)
    d, ok = make_lens(spec, size).pixel_to_dir(xy)
    want = np.array([v360_dir(x, y, w, h, lon, lat) for x, y in xy])
    assert ok.all()
    # the test's own radians and divisions round otherwise than the model's steps: a few ulps of the angles
    np.testing.assert_allclose(d, want, rtol=0, atol=1e-14)


def test_the_pinned_v360_point_and_the_exact_poles():
    lens = make_lens("equirect", (800, 400))
    d, ok = lens.pixel_to_dir(np.array([[620.25, 130.5], [0.0, 0.0], [321.0, 0.0], [5.5, 400.0], [800.0, 400.0]]))
    assert ok.all()
    np.testing.assert_allclose(d[0], (0.8438986849711829, 0.5191462344390729, -0.13535950935061536), rtol=0, atol=ULPS)
    assert d[1:3].tolist() == [[0.0, 1.0, 0.0]] * 2 and d[3:].tolist() == [[0.0, -1.0, 0.0]] * 2


def test_a_model_that_changes_its_steps_has_no_kernel():
    class Shifted(Equirect):
        def _pixel_to_dir(self, xy):
            return super()._pixel_to_dir(xy + 1.0)

    lens = Shifted(360, 180)
    assert lens.dir_kernel() is None
    got, _ = lens.pixel_to_dir(np.array([[179.0, 89.0]]))
    np.testing.assert_allclose(got, [v360_dir(180.0, 90.0, 360, 180)], rtol=0, atol=1e-15)
