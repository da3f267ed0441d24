"""Projecting directions into a source: the vectorised ``dir_to_pixel`` (small calls) and the lens's compiled
kernel (large calls) give the same pixels, both equal to the equirect formula transcribed here in float64."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from lenslab.lenses.projections.equirect import Equirect
from lenslab.warp import maps

# 1e-9 px: the two paths and the formula differ only in the last bits of atan2 (about 1e-12 px
# measured at 4096 px wide); 1e-9 px is still a thousand times below anything a float32 map resolves
TOL = 1e-9


def formula(d, w, h, lon=(-180.0, 180.0), lat=(-90.0, 90.0)):
    """phi = atan2(dx, dz), theta = atan2(dy, hypot(dx, dz)); x, y linear in them (pixel centres +0.5)."""
    phi = np.arctan2(d[:, 0], d[:, 2])
    theta = np.arctan2(d[:, 1], np.hypot(d[:, 0], d[:, 2]))
    lon0, lon1 = np.radians(lon)
    lat0, lat1 = np.radians(lat)
    x = (phi - lon0) / (lon1 - lon0) * w
    y = (lat1 - theta) / (lat1 - lat0) * h
    valid = (phi >= lon0) & (phi <= lon1) & (theta >= lat0) & (theta <= lat1)
    return np.stack([x, y], axis=-1), valid


@pytest.fixture
def dirs():
    rng = np.random.default_rng(7)
    d = rng.normal(size=(2000, 3)) * rng.uniform(0.1, 10.0, size=(2000, 1))  # any length
    return np.concatenate([d, [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.3, 0.9, 0.2]]])


@pytest.mark.parametrize("span", [{}, {"lon_min": -90.0, "lon_max": 90.0, "lat_min": -45.0, "lat_max": 60.0}])
def test_small_and_compiled_projection_match_the_formula(dirs, span, monkeypatch):
    lens = Equirect(4096, 2048, **span)
    want, want_ok = formula(dirs, 4096, 2048, (lens.lon_min, lens.lon_max), (lens.lat_min, lens.lat_max))
    assert len(dirs) < maps.COMPILED_PROJECT_MIN  # this call takes the vectorised path
    small, small_ok = maps.project(lens, dirs)
    monkeypatch.setattr(maps, "COMPILED_PROJECT_MIN", 1)  # and now the compiled kernel
    big, big_ok = maps.project(lens, dirs)
    for xy, ok in ((small, small_ok), (big, big_ok)):
        np.testing.assert_array_equal(ok, want_ok)
        np.testing.assert_allclose(xy[ok], want[ok], rtol=0, atol=TOL)
        assert np.all(xy[~ok] == 0.0)
    np.testing.assert_allclose(small, big, rtol=0, atol=TOL)


def test_the_compiled_projection_needs_no_jit():
    """The lens's kernel is a function of the C++ extension: asking for it and running it compiles nothing."""
    kern = Equirect(512, 256).pixel_kernel()
    assert type(kern.fn).__module__ == "nanobind" and type(kern.fn).__name__ == "nb_func"
    assert not hasattr(kern.fn, "signatures")  # not a numba dispatcher
