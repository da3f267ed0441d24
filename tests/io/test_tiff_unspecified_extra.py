"""A TIFF extra sample tagged unspecified data (ExtraSamples 0, tifffile's default for grey plus one channel) is no
alpha: lenslab reads every value as stored, as OpenImageIO does (which names it a plain channel), instead of
multiplying the other channels by it. A 2-channel ST map (s, t) so written keeps its s; unassociated alpha (2) is
still straight colour, premultiplied on reading."""

from __future__ import annotations

import numpy as np
import pytest
import tifffile

import lenslab.io as lio

oiio = pytest.importorskip("OpenImageIO")


def _oiio(path) -> tuple[np.ndarray, int]:
    buf = oiio.ImageBuf(str(path))
    return buf.get_pixels(oiio.FLOAT), buf.spec().alpha_channel


def test_a_two_channel_float_st_map_keeps_its_values(tmp_path):
    h, w = 6, 8
    y, x = np.mgrid[0:h, 0:w] + 0.5
    st = np.dstack([x / w, 1 - y / h]).astype(np.float32)
    path = tmp_path / "st.tif"
    tifffile.imwrite(path, st, photometric="minisblack", planarconfig="contig")
    assert [int(v) for v in tifffile.TiffFile(path).pages[0].extrasamples] == [0]  # unspecified
    theirs, alpha = _oiio(path)
    assert alpha == -1  # OpenImageIO: no alpha channel
    image, _ = lio.read(path)
    np.testing.assert_array_equal(image, theirs)
    np.testing.assert_array_equal(image[..., 0], st[..., 0])


def test_eight_bit_rgb_plus_unspecified_is_read_as_openimageio_reads_it(tmp_path):
    rng = np.random.default_rng(3)
    codes = rng.integers(0, 256, (5, 7, 4), dtype=np.uint8)
    path = tmp_path / "rgbx.tif"
    tifffile.imwrite(path, codes, photometric="rgb", extrasamples=["unspecified"])
    theirs, alpha = _oiio(path)
    assert alpha == -1
    image, _ = lio.read(path, raw=False)
    np.testing.assert_allclose(image[..., 3], theirs[..., 3], rtol=0, atol=1e-6)  # the fourth channel: code / 255
    # colour: sRGB codes decoded to linear (the sRGB formula, in float64), not multiplied by the fourth channel
    v = codes[..., :3].astype(np.float64) / 255
    linear = np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4)
    np.testing.assert_allclose(image[..., :3], linear, rtol=0, atol=2e-6)


def test_unassociated_alpha_is_still_premultiplied(tmp_path):
    rgba = np.array([[[1.0, 0.5, 0.25, 0.5]]], np.float32)
    path = tmp_path / "straight.tif"
    tifffile.imwrite(path, rgba, photometric="rgb", extrasamples=["unassalpha"])
    image, _ = lio.read(path)
    np.testing.assert_allclose(image[0, 0], [0.5, 0.25, 0.125, 0.5], rtol=0, atol=1e-7)
