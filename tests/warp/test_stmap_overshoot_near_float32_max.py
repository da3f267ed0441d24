"""A warp by an ST map of finite values near float32's largest, whose bicubic or Lanczos overshoot passes it,
holds the largest float32 there, as the lens-to-lens warp of the same geometry (equirect -> equirect of the same
size, the identity) does, bit for bit, and neither says anything of it (no output value was ever non-finite: the
samplers hold the largest float32, :mod:`lenslab.warp.filters`).

Outside value: the source is 1 but for a 5x5 island of +-3.3e38 signed as the averaged weights of 4 stratified
bicubic samples (offsets +-1/4 pixel); the output is the mean over those samples of the Catmull-Rom sums
(``w(t) = 1.5|t|^3 - 2.5|t|^2 + 1`` for ``|t| < 1``, ``-0.5|t|^3 + 2.5|t|^2 - 4|t| + 2`` for ``|t| < 2``), worked
here in float64 and clipped to +-``numpy.finfo(numpy.float32).max``: 3.3e38 times 1.0957 at the island's centre."""

from __future__ import annotations

import numpy as np

from lenslab.cli.main import main
from lenslab.io import read, write

W, H = 32, 16
BIG = float(np.finfo(np.float32).max)


def _catmull_rom(t):
    t = np.abs(t)
    return np.where(t < 1, 1.5 * t**3 - 2.5 * t**2 + 1, np.where(t < 2, -0.5 * t**3 + 2.5 * t**2 - 4 * t + 2, 0.0))


def _expected(src):
    out = np.zeros(src.shape, np.float64)
    for dy in (-0.25, 0.25):
        for dx in (-0.25, 0.25):
            for j in range(H):
                for i in range(W):
                    x, y = i + dx, j + dy  # the sample in index coordinates (pixel centres at integers)
                    xs, ys = np.arange(int(np.floor(x)) - 1, int(np.floor(x)) + 3), \
                        np.arange(int(np.floor(y)) - 1, int(np.floor(y)) + 3)
                    wx, wy = _catmull_rom(xs - x), _catmull_rom(ys - y)
                    taps = src[np.clip(ys, 0, H - 1)][:, np.clip(xs, 0, W - 1)].astype(np.float64)
                    out[j, i] += np.einsum("y,x,yxc->c", wy, wx, taps) / 4
    return np.clip(out, -BIG, BIG)


def test_stmap_overshoot_near_float32_max_is_the_lens_warps(tmp_path, capsys):
    src = np.ones((H, W, 3), np.float32)
    sign = np.array([-1.0, 1.0, 1.0, 1.0, -1.0])
    src[6:11, 14:19] = (3.3e38 * np.outer(sign, sign))[..., None]
    write(tmp_path / "src.exr", src, pixel_type="float")
    assert main(["stmap", "--from", "equirect", "--to", "equirect", "--size", f"{W}x{H}", "-o",
                 str(tmp_path / "id.exr"), "-q"]) == 0
    outs = {}
    ways = {"st": ["--stmap", str(tmp_path / "id.exr")], "lens": ["--to", "equirect", "--size", f"{W}x{H}"]}
    for name, how in ways.items():
        outs[name] = tmp_path / f"{name}.exr"
        assert main(["warp", str(tmp_path / "src.exr"), *how, "-o", str(outs[name]), "--filter", "bicubic",
                     "--samples", "4", "--pixel-type", "float", "--no-alpha"]) == 0
    st, lens = read(outs["st"])[0], read(outs["lens"])[0]
    assert "float32's range" not in capsys.readouterr().err
    assert np.isfinite(st).all()
    np.testing.assert_array_equal(st, lens)
    expected = _expected(src)
    assert expected[8, 16, 0] == BIG and st[8, 16, 0] == np.float32(BIG)
    # float64 weights summed in another order, stored in float32: a few ulps of each value
    np.testing.assert_allclose(st, expected, rtol=1e-6, atol=1e-6)
