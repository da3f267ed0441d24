"""An ST map stored as integer codes (a 16- or 8-bit PNG or TIFF from another tool) holds coordinates,
not colours: s and t are the codes over their maximum, as Nuke reads a map whose colourspace is raw.
The maps are written by OpenCV and tifffile from Nuke's STMap formula transcribed here in float64."""
import cv2
import numpy as np
import pytest
import tifffile

from lenslab.stmap import read_st_map


def _identity_codes(w, h, maxval, dtype):
    """Nuke's STMap of the identity warp: s = (x + 0.5) / W, t = 1 - (y + 0.5) / H, as integer codes."""
    x = (np.arange(w, dtype=np.float64) + 0.5) / w
    y = 1.0 - (np.arange(h, dtype=np.float64) + 0.5) / h
    s, t = np.meshgrid(x, y)
    codes = np.stack([s, t, np.zeros_like(s)], axis=-1)
    return np.round(codes * maxval).astype(dtype)


@pytest.mark.parametrize("bits", [8, 16])
def test_png_map_reads_its_codes_not_srgb(tmp_path, bits):
    maxval, dtype = (255, np.uint8) if bits == 8 else (65535, np.uint16)
    rgb = _identity_codes(64, 32, maxval, dtype)
    path = tmp_path / "map.png"
    assert cv2.imwrite(str(path), rgb[..., ::-1])  # OpenCV writes BGR
    st = read_st_map(path)
    # the codes themselves over their maximum: exact up to float32's rounding of the quotient
    np.testing.assert_allclose(st[..., 0], rgb[..., 0] / maxval, rtol=0, atol=1e-7)
    np.testing.assert_allclose(st[..., 1], rgb[..., 1] / maxval, rtol=0, atol=1e-7)
    assert st[..., 3].min() == 1.0


def test_16bit_tiff_map_reads_its_codes(tmp_path):
    rgb = _identity_codes(40, 20, 65535, np.uint16)
    path = tmp_path / "map.tif"
    tifffile.imwrite(path, rgb, photometric="rgb")
    st = read_st_map(path)
    np.testing.assert_allclose(st[..., :2], rgb[..., :2] / 65535, rtol=0, atol=1e-7)
