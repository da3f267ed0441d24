"""The map lattice's field test compiled (``outside_field``, ``src/native/lattice_field.cpp``): the cells of an output
none of whose samples the source sees, which the lattice leaves unseen without evaluating them.

Against its NumPy reference (:func:`lenslab.warp.kernels.lattice_reference.outside_field`, the steps it replaced) on
lattices of random cameras drawn by hypothesis (pinholes of 0.5 to 179.5 degrees and fisheyes of every mapping up to
360 degrees, any pose, outputs of several models): the same cells. The kernel decides a cone's test by a cosine
comparison where it is clear by 1e-12 and by the reference's arc cosine otherwise; the arc cosines come from glibc's
vector maths, NumPy's from its own loops, both within a few ulps, far inside the 1e-9 rad of slack both add.

Against geometry transcribed here: for a pinhole looking along +z and an equirect output, every sample of a cell the
kernel calls outside (8 x 8 samples per cell, at pixel centres) lands outside the frame by the pinhole projection
``x = W/2 (1 + (dx/dz) / tan(fov/2))``, ``y = H/2 (1 - (dy/dz) / (tan(fov/2) H/W))`` or behind the eye, its ray
from the latitude/longitude definition (v360's ``equirect``); and most of the panorama is outside.
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

import lenslab.warp.maps as maps
from lenslab.lenses import Camera
from lenslab.warp import lattice
from lenslab.warp.kernels import lattice_reference as ref

W, H, FOV, OW, OH = 400, 300, 70.0, 720, 360


def v360_rays(x, y):
    lon = np.radians(-180.0 + x / OW * 360.0)
    lat = np.radians(90.0 - y / OH * 180.0)
    return np.stack([np.cos(lat) * np.sin(lon), np.sin(lat), np.cos(lat) * np.cos(lon)], -1)


def pinhole_sees(d):
    t = np.tan(np.radians(FOV) / 2.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        x = W / 2.0 * (1.0 + d[..., 0] / d[..., 2] / t)
        y = H / 2.0 * (1.0 - d[..., 1] / d[..., 2] / (t * H / W))
    return (d[..., 2] > 0) & (x >= 0) & (x <= W) & (y >= 0) & (y <= H)


def test_no_sample_of_a_cell_outside_the_photos_field_is_seen():
    lens = Camera.from_spec(f"perspective:fov={FOV}", (W, H)).lens
    s = maps.LATTICE_STEP
    ncx, ncy = OW // s, OH // s
    xn, yn = np.meshgrid((np.arange(ncx + 3) - 1.0) * s, (np.arange(ncy + 3) - 1.0) * s)
    dirs = v360_rays(xn, yn)
    have = (yn >= 0) & (yn <= OH)  # nodes beyond the top and bottom rows have no ray
    out = lattice.outside_field(lens.field(), dirs, have, pinhole_sees(dirs))
    assert out.shape == (ncy, ncx)
    assert 0.9 < out.mean() < 0.99  # a 70-degree photo leaves most of the panorama
    np.testing.assert_array_equal(out, ref.outside_field(lens.field(), dirs, have, pinhole_sees(dirs)))
    # every sample of every cell called outside: 8 x 8 pixel centres
    py, px = np.mgrid[0:OH, 0:OW] + 0.5
    seen = pinhole_sees(v360_rays(px, py))
    cell_seen = seen.reshape(ncy, s, ncx, s).any(axis=(1, 3))
    assert cell_seen.sum() > 100
    assert not (out & cell_seen).any()


MAPPINGS = {"equidistant": 360.0, "equisolid": 360.0, "stereographic": 359.0, "orthographic": 180.0}
OUTPUTS = ["equirect", "fisheye:fov=180", "perspective:fov=100", "cylindrical", "fisheye:fov=300"]


@st.composite
def cameras(draw):
    if draw(st.booleans()):
        spec = f"perspective:fov={draw(st.floats(0.5, 179.5))!r}"
        size = (draw(st.integers(16, 600)), draw(st.integers(16, 600)))
    else:
        mapping = draw(st.sampled_from(sorted(MAPPINGS)))
        spec = f"fisheye:mapping={mapping},fov={draw(st.floats(1.0, MAPPINGS[mapping]))!r}"
        size = (draw(st.integers(16, 600)),) * 2
    angle = st.floats(-180.0, 180.0)
    src = Camera.from_spec(spec, size, yaw=draw(angle), pitch=draw(st.floats(-90.0, 90.0)), roll=draw(angle))
    out = draw(st.sampled_from(OUTPUTS))
    w = draw(st.integers(64, 500))
    dst = Camera.from_spec(out, (w, w // 2 if out == "equirect" else draw(st.integers(64, 500))),
                           yaw=draw(angle), pitch=draw(st.floats(-90.0, 90.0)))
    return src, dst


@settings(max_examples=60, deadline=None)
@given(cameras())
def test_the_kernel_gives_its_references_cells_on_any_lattice(pair):
    src, dst = pair
    calls = []

    def both(field, dirs, have, seen):
        got = lattice.outside_field(field, dirs, have, seen)
        calls.append((got, ref.outside_field(field, dirs, have, seen)))
        return got

    real = maps.outside_field
    maps.outside_field = both
    try:
        maps.Mapper(src, dst)
    finally:
        maps.outside_field = real
    for got, want in calls:
        np.testing.assert_array_equal(got, want)


def test_no_field_no_cells():
    assert lattice.outside_field(None, np.zeros((5, 5, 3)), np.ones((5, 5), bool), np.zeros((5, 5), bool)) is None
