"""A warp of two data channels (``u, v``: no channel named ``A``) keeps them as data: not clipped to
[0, 1], not premultiplied or divided by the second one; the warp's coverage is written beside them as
``A``. OpenImageIO reads the output (names, alpha channel); the expected values are the source's own,
since an equirect -> equirect warp of the same size and lens samples every output pixel centre on a
source pixel centre (bilinear weights 1 and 0 up to the float64 round-off of the pixel-centre map, ~1e-16:
a value moves by at most a few float32 ulps, or ~1e-16 x its neighbour where it is 0)."""

from __future__ import annotations

import numpy as np
import pytest

from lenslab.cli.main import main

OpenEXR = pytest.importorskip("OpenEXR")
oiio = pytest.importorskip("OpenImageIO")

H, W = 8, 16


def _warped(path):
    """(names, alpha index, pixels) of a warp of ``u, v`` as OpenImageIO reads it, with its names checked."""
    inp = oiio.ImageInput.open(str(path))
    spec = inp.spec()
    pixels = np.asarray(inp.read_image(0, 0, 0, spec.nchannels, "float"), np.float32)
    inp.close()
    names = tuple(spec.channelnames)
    assert sorted(names) == ["A", "u", "v"] and names[spec.alpha_channel] == "A"  # EXR lists names in order
    return names, spec.alpha_channel, pixels


def test_warp_keeps_two_data_channels(tmp_path):
    u = np.linspace(0.0, 5.0, H * W, dtype=np.float32).reshape(H, W)
    v = np.linspace(-5.0, 5.0, H * W, dtype=np.float32).reshape(H, W)
    OpenEXR.File({"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage},
                 {"u": u, "v": v}).write(str(tmp_path / "uv.exr"))
    assert main(["warp", str(tmp_path / "uv.exr"), "-o", str(tmp_path / "w.exr"), "--from", "equirect", "--to",
                 "equirect", "--size", f"{W}x{H}", "--pixel-type", "float", "-q"]) == 0
    names, alpha, pixels = _warped(tmp_path / "w.exr")
    wu, wv = pixels[..., names.index("u")], pixels[..., names.index("v")]
    assert wv.min() < 0.0 and wv.max() > 1.0  # not clipped to [0, 1]
    np.testing.assert_allclose(wv, v, rtol=1e-6, atol=1e-12)  # not premultiplied, not divided by v
    np.testing.assert_allclose(wu, u, rtol=1e-6, atol=1e-12)
    np.testing.assert_array_equal(pixels[..., alpha], 1.0)  # the coverage: all seen


def test_warp_through_an_st_map_keeps_two_data_channels(tmp_path):
    """The same with an ST map of the identity (lenslab's own ``stmap`` command): exact, for the same
    reason as above."""
    u = np.linspace(0.0, 5.0, H * W, dtype=np.float32).reshape(H, W)
    v = np.linspace(-5.0, 5.0, H * W, dtype=np.float32).reshape(H, W)
    OpenEXR.File({"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage},
                 {"u": u, "v": v}).write(str(tmp_path / "uv.exr"))
    from lenslab import Camera
    from lenslab.stmap import st_map, write_st_map

    cam = Camera.from_spec("equirect", (W, H))
    write_st_map(tmp_path / "st.exr", st_map(cam, cam))
    assert main(["warp", str(tmp_path / "uv.exr"), "-o", str(tmp_path / "w.exr"), "--stmap", str(tmp_path / "st.exr"),
                 "--pixel-type", "float", "-q"]) == 0
    names, alpha, pixels = _warped(tmp_path / "w.exr")
    np.testing.assert_allclose(pixels[..., names.index("v")], v, rtol=1e-6, atol=1e-12)
    np.testing.assert_allclose(pixels[..., names.index("u")], u, rtol=1e-6, atol=1e-12)
