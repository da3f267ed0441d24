"""The warp engine asks lenses what it needs: no model name in lenslab/warp, and a new model that only
states its normalised maps warps correctly with the protocol's defaults."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

import lenslab.warp
from lenslab.lenses import REGISTRY, Camera, Lens
from lenslab.lenses.core.protocol import Piece, Seams
from lenslab.warp import warp


def test_no_lens_model_name_in_the_engine():
    names = "|".join(map(re.escape, sorted(REGISTRY, key=len, reverse=True)))
    # a model name in quotes (a comparison, a set of names) or any read of a lens's name
    pattern = re.compile(r"""["'](""" + names + r""")["']|\.name\b|getattr\([^)]*["']name["']""", re.IGNORECASE)
    hits = [f"{p.name}:{i}: {line.strip()}" for p in sorted(Path(lenslab.warp.__file__).parent.rglob("*.py"))
            for i, line in enumerate(p.read_text().splitlines(), 1) if pattern.search(line)]
    assert hits == []


class Stereo(Lens):
    """A test model stating only its normalised maps: stereographic, r = 2 tan(theta / 2) (theta from
    the axis), the image's half width at r = 1."""

    name = ""

    def uv_to_dir(self, uv):
        u, v = uv[..., 0], uv[..., 1]
        r2 = u * u + v * v
        d = np.stack([4 * u, 4 * v, 4 - r2], axis=-1) / (4 + r2)[..., None]
        return d, np.ones(uv.shape[:-1], bool)

    def dir_to_uv(self, d):
        k = 2.0 / (1.0 + d[..., 2])
        ok = d[..., 2] > -0.99
        return np.stack([d[..., 0] * k, d[..., 1] * k], axis=-1) * ok[..., None], ok


def test_a_model_with_only_its_normalised_maps_warps_with_the_defaults():
    lens = Stereo(48, 48)
    assert lens.seams() == Seams() and lens.pieces() == (Piece(0.0, 0.0, 48.0, 48.0),)
    assert lens.pixel_kernel() is None and lens.channel_lenses() is None and lens.falloff([[1.0, 1.0]]) is None
    src = Camera.from_spec("equirect", (256, 128))
    img = np.broadcast_to(np.arange(256, dtype=np.float32)[None, :, None], (128, 256, 1)).copy()
    out, alpha = warp(img, src, Camera(lens))
    # the ray of pixel centre (x, y) by the stereographic formula above, read on the ramp at its
    # equirect column (atan2(dx, dz)/pi + 1) W/2, index minus 1/2 (bilinear reads a ramp exactly)
    y, x = np.mgrid[0:48, 0:48] + 0.5
    u, v = 2 * x / 48 - 1, 1 - 2 * y / 48
    r2 = u * u + v * v
    want = (np.arctan2(4 * u, 4 - r2) / np.pi + 1) * 128 - 0.5
    assert alpha.min() == 1.0
    # float32 maps interpolated on the checked lattice: within 1/200 source px (lenslab.warp.maps)
    np.testing.assert_allclose(out[..., 0], want, atol=5e-3)


def test_the_compiled_panorama_inverse_is_the_conventions_formula():
    from lenslab.lenses import make_lens
    from lenslab.warp.maps import project

    rng = np.random.default_rng(5)
    d = rng.normal(size=(5000, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    lens = make_lens("equirect", (1000, 500))
    assert lens.pixel_kernel() is not None
    xy, valid = project(lens, d)
    # x = (atan2(dx, dz)/pi + 1) W/2, y = (1 - atan2(dy, hypot(dx, dz)) / (pi/2)) H/2
    want_x = (np.arctan2(d[:, 0], d[:, 2]) / np.pi + 1) * 500
    want_y = (1 - np.arctan2(d[:, 1], np.hypot(d[:, 0], d[:, 2])) / (np.pi / 2)) * 250
    assert valid.all()
    # libm's atan2 and NumPy's vectorised one differ by an ulp or two: 1e-12 px at 1000 px
    np.testing.assert_allclose(xy[:, 0], want_x, atol=1e-9)
    np.testing.assert_allclose(xy[:, 1], want_y, atol=1e-9)
    # a partial range: longitudes -90..90, latitudes -45..60; outside it nothing is seen
    part = make_lens("equirect:lon_min=-90,lon_max=90,lat_min=-45,lat_max=60", (360, 210))
    pxy, pv = project(part, d)
    lon, lat = np.degrees(np.arctan2(d[:, 0], d[:, 2])), np.degrees(np.arctan2(d[:, 1], np.hypot(d[:, 0], d[:, 2])))
    inside = (np.abs(lon) <= 90) & (lat >= -45) & (lat <= 60)
    np.testing.assert_array_equal(pv, inside)
    np.testing.assert_allclose(pxy[pv, 0], (lon[pv] + 90) / 180 * 360, atol=1e-9)
    np.testing.assert_allclose(pxy[pv, 1], (60 - lat[pv]) / 105 * 210, atol=1e-9)
    assert np.all(pxy[~pv] == 0)
