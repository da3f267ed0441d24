"""``lenslab warp`` develops its output in the output's own memory (the source freed first): the
exposure is still light times 2**stops on colour with alpha kept (the OpenEXR convention of
premultiplied colour), read back by OpenImageIO from the EXR files written."""

from __future__ import annotations

import sys

import numpy as np
import pytest

import lenslab.io as lio
from tests.hostile_run import run

oiio = pytest.importorskip("OpenImageIO")


def _read(path):
    inp = oiio.ImageInput.open(str(path))
    assert inp is not None, oiio.geterror()
    pixels = np.asarray(inp.read_image("float"))
    inp.close()
    return pixels


def test_warp_exposure_with_alpha_is_colour_times_two_to_the_stops(tmp_path):
    rng = np.random.default_rng(1)
    img = rng.random((64, 128, 4), dtype=np.float32)
    img[..., :3] *= img[..., 3:]
    src = tmp_path / "src.exr"
    lio.write(src, img, pixel_type="float")
    outs = {}
    for stops in ("0", "1.5"):
        out = tmp_path / f"w{stops}.exr"
        done = run([sys.executable, "-m", "lenslab", "warp", str(src), "-o", str(out), "--to", "fisheye:fov=180",
                    "--size", "48x48", "--exposure", stops, "--pixel-type", "float", "-q"])
        assert done.returncode == 0, done.stderr
        outs[stops] = _read(out)
    plain, exposed = outs["0"], outs["1.5"]
    assert plain.shape == (48, 48, 4) and plain[..., 3].max() > 0.5
    assert np.array_equal(exposed[..., 3], plain[..., 3])  # coverage is not light
    expected = (plain[..., :3].astype(np.float64) * 2.0 ** 1.5).astype(np.float32)
    np.testing.assert_allclose(exposed[..., :3], expected, rtol=2e-7, atol=0)  # one float32 rounding
