"""``lenslab convert`` of an ST map that ``lenslab stmap`` wrote (its EXR header says ``lenslab:stmap``) to PNG
or PPM stores s, t and A as raw codes over their maximum (16-bit by default), as OpenCV, tifffile and Nuke
(colourspace raw) store maps, never tone-mapped or sRGB-encoded: the codes OpenCV reads back are Nuke's
STMap formula, transcribed here in float64, times 65535; and ``warp --stmap`` with the PNG gives the EXR map's
warp."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

import lenslab.io as lio
from lenslab.cli.main import main


def _identity_map(tmp_path, w=64, h=32):
    path = tmp_path / "st.exr"
    assert main(["stmap", "--from", "equirect", "--to", "equirect", "--size", f"{w}x{h}", "-o", str(path), "-q"]) == 0
    return path


def test_png_holds_the_maps_codes(tmp_path):
    w, h = 64, 32
    st = _identity_map(tmp_path, w, h)
    png = tmp_path / "st16.png"
    assert main(["convert", str(st), "-o", str(png), "-q"]) == 0
    codes = cv2.imread(str(png), cv2.IMREAD_UNCHANGED)  # B G R A
    assert codes.dtype == np.uint16 and codes.shape == (h, w, 4)
    s = (np.arange(w, dtype=np.float64) + 0.5) / w  # Nuke's STMap of the identity at pixel centres
    t = 1.0 - (np.arange(h, dtype=np.float64) + 0.5) / h
    # the nearest code: half a code of rounding, at most (the map is float32, far finer than 1/65535)
    np.testing.assert_allclose(codes[..., 2], np.broadcast_to(s * 65535, (h, w)), rtol=0, atol=0.5 + 1e-3)
    np.testing.assert_allclose(codes[..., 1], np.broadcast_to((t * 65535)[:, None], (h, w)), rtol=0, atol=0.5 + 1e-3)
    assert (codes[..., 3] == 65535).all()


def test_8bit_ppm_holds_the_maps_codes(tmp_path):
    w, h = 32, 16
    st = _identity_map(tmp_path, w, h)
    ppm = tmp_path / "st8.ppm"
    assert main(["convert", str(st), "-o", str(ppm), "--bits", "8", "-q"]) == 0
    codes = cv2.imread(str(ppm), cv2.IMREAD_UNCHANGED)[..., ::-1]
    s = (np.arange(w, dtype=np.float64) + 0.5) / w
    np.testing.assert_array_equal(codes[0, :, 0], np.round(s * 255))


def test_warp_by_the_png_map_is_the_warp_by_the_exr_map(tmp_path):
    st = tmp_path / "st.exr"
    assert main(["stmap", "--from", "fisheye:fov=180", "--to", "perspective:fov=90", "--size", "48x32",
                 "--source-size", "64x64", "-o", str(st), "-q"]) == 0
    png = tmp_path / "st16.png"
    assert main(["convert", str(st), "-o", str(png), "-q"]) == 0
    yy, xx = np.mgrid[0:64, 0:64].astype(np.float32)
    src = lio.write(tmp_path / "src.exr", np.dstack([xx, yy, np.zeros_like(xx)]))  # each pixel holds its place
    outs = []
    for m in (st, png):
        out = tmp_path / f"out-{m.suffix[1:]}.exr"
        assert main(["warp", str(src), "-o", str(out), "--stmap", str(m), "--filter", "bilinear", "--pixel-type", "float", "-q"]) == 0
        outs.append(lio.read(out)[0])
    ok = outs[0][..., 3] > 0
    # a 16-bit code moves s by 1/131070 at most: 64/131070 source px; 1e-3 px is float32's own rounding
    np.testing.assert_allclose(outs[1][ok][:, :2], outs[0][ok][:, :2], rtol=0, atol=64 / 131070 + 1e-3)


def test_16bit_tiff_holds_the_maps_codes(tmp_path):
    tifffile = pytest.importorskip("tifffile")
    w, h = 64, 32
    st = _identity_map(tmp_path, w, h)
    tif = tmp_path / "st.tif"
    assert main(["convert", str(st), "-o", str(tif), "--bits", "16", "-q"]) == 0
    codes = tifffile.imread(tif)
    assert codes.dtype == np.uint16
    s = (np.arange(w, dtype=np.float64) + 0.5) / w
    np.testing.assert_allclose(codes[0, :, 0], s * 65535, rtol=0, atol=0.5 + 1e-3)  # the nearest code
