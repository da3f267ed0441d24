"""The warp engine asks lenses what it needs: no model name in lenslab/warp, and a new model that only
states its normalised maps warps correctly with the protocol's defaults."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

import lenslab.warp
from lenslab.lenses import REGISTRY, Camera, Lens
from lenslab.lenses.protocol import Piece, Seams
from lenslab.warp import warp


def test_no_lens_model_name_in_the_engine():
    names = "|".join(map(re.escape, sorted(REGISTRY, key=len, reverse=True)))
    # a model name in quotes (a comparison, a set of names) or any read of a lens's name
    pattern = re.compile(r"""["'](""" + names + r""")["']|\.name\b|getattr\([^)]*["']name["']""", re.IGNORECASE)
    hits = [f"{p.name}:{i}: {line.strip()}" for p in sorted(Path(lenslab.warp.__file__).parent.glob("*.py"))
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
