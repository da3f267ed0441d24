"""OpenColorIO display transforms: lenslab's path against PyOpenColorIO's own processor on the same pixels."""

from __future__ import annotations

import cv2
import numpy as np
import pytest
import tifffile

PyOpenColorIO = pytest.importorskip("PyOpenColorIO")

import lenslab.io as lio  # noqa: E402
from lenslab.cli.main import main  # noqa: E402
from lenslab.io.ocio import display_transform  # noqa: E402

SDR = ("sRGB - Display", "ACES 2.0 - SDR 100 nits (Rec.709)")
PQ = ("Rec.2100-PQ - Display", "ACES 2.0 - HDR 1000 nits (Rec.2020)")


def _scene(h=6, w=10, seed=0):
    rng = np.random.default_rng(seed)
    img = (np.exp2(rng.uniform(-6, 6, (h, w, 3)))).astype(np.float32)  # 12 stops of scene light
    img[0, 0] = 0.0
    return img


def _reference(img, display, view, colorspace="Linear Rec.709 (sRGB)", config="ocio://default"):
    """PyOpenColorIO's own processor (the legacy colour space / display / view call), applied as it documents."""
    cfg = PyOpenColorIO.Config.CreateFromFile(config)
    proc = cfg.getProcessor(colorspace, display, view, PyOpenColorIO.TRANSFORM_DIR_FORWARD)
    out = np.ascontiguousarray(img, np.float32).copy()
    proc.getDefaultCPUProcessor().applyRGB(out)
    return out


@pytest.mark.parametrize("display, view", [SDR, PQ, ("Display P3 - Display", "Un-tone-mapped"),
                                           ("Rec.1886 Rec.709 - Display", "Video (colorimetric)")])
def test_same_pixels_as_pyopencolorio(display, view):
    img = _scene()
    ours = display_transform(img, display, view)
    # the same float32 CPU processor on the same pixels: 1e-5 leaves room only for float32 rounding
    np.testing.assert_allclose(ours, _reference(img, display, view), atol=1e-5, rtol=0)


def test_short_names_alpha_grey_and_other_colorspaces():
    img = _scene()
    rgba = np.concatenate([img, np.full(img.shape[:2] + (1,), 0.25, np.float32)], axis=-1)
    out = display_transform(rgba, "srgb", "sdr 100 nits (rec.709)")
    np.testing.assert_allclose(out[..., :3], _reference(img, *SDR), atol=1e-5, rtol=0)  # float32 rounding
    assert (out[..., 3] == 0.25).all()  # alpha passes through
    grey = display_transform(img[..., :1], *SDR)
    np.testing.assert_allclose(grey[..., 0], _reference(np.repeat(img[..., :1], 3, -1), *SDR)[..., 0], atol=1e-5)
    acescg = display_transform(img, *SDR, colorspace="ACEScg")
    np.testing.assert_allclose(acescg, _reference(img, *SDR, colorspace="ACEScg"), atol=1e-5, rtol=0)


def test_hlg_from_the_studio_config():
    img = _scene()
    cfg = "ocio://studio-config-latest"
    names = list(PyOpenColorIO.Config.CreateFromFile(cfg).getViews("Rec.2100-HLG - Display"))
    view = next(v for v in names if "HDR" in v)
    ours = display_transform(img, "rec.2100-hlg", view, config=cfg)
    np.testing.assert_allclose(ours, _reference(img, "Rec.2100-HLG - Display", view, config=cfg), atol=1e-5, rtol=0)


def test_convert_writes_the_display_codes(tmp_path):
    img = _scene()
    lio.write(tmp_path / "s.exr", img, pixel_type="float")
    assert main(["convert", str(tmp_path / "s.exr"), "--to", "png", "--bits", "16", "--display", "srgb",
                 "--view", "ACES 2.0 - SDR", "-o", str(tmp_path / "s.png"), "-q"]) == 0
    codes = cv2.imread(str(tmp_path / "s.png"), cv2.IMREAD_UNCHANGED)[..., ::-1].astype(np.float64)
    want = np.clip(_reference(img, *SDR), 0, 1).astype(np.float64) * 65535
    assert np.abs(codes - want).max() <= 0.5 + 65535 * 1e-5  # rounding to the nearest code, plus 1e-5 of OCIO
    # an HDR display: 16-bit PNG by default, PQ code values straight from OpenColorIO
    assert main(["convert", str(tmp_path / "s.exr"), "--to", "png", "--display", "rec.2100-pq",
                 "--view", "1000 nits (rec.2020)", "-o", str(tmp_path / "pq.png"), "-q"]) == 0
    pq = cv2.imread(str(tmp_path / "pq.png"), cv2.IMREAD_UNCHANGED)
    assert pq.dtype == np.uint16
    want = np.clip(_reference(img, *PQ), 0, 1).astype(np.float64) * 65535
    assert np.abs(pq[..., ::-1] - want).max() <= 0.5 + 65535 * 1e-5
    # TIFF has no tag that says PQ: refused before any work (PNG's cICP chunk says it)
    assert main(["convert", str(tmp_path / "s.exr"), "--to", "tiff", "--display", "rec.2100-pq",
                 "--view", "1000 nits (rec.2020)", "-o", str(tmp_path / "pq.tif"), "-q"]) == 2
    assert not (tmp_path / "pq.tif").exists()
    assert main(["convert", str(tmp_path / "s.exr"), "--to", "tiff", "--display", "srgb",
                 "--view", "ACES 2.0 - SDR", "-o", str(tmp_path / "sdr.tif"), "-q"]) == 0
    assert tifffile.imread(tmp_path / "sdr.tif").dtype == np.uint16
    # 8-bit JPEG cannot hold PQ: a usage error before any work, as is an unknown display
    assert main(["convert", str(tmp_path / "s.exr"), "--to", "jpg", "--display", "rec.2100-pq",
                 "-o", str(tmp_path / "pq.jpg"), "-q"]) == 2
    assert main(["convert", str(tmp_path / "s.exr"), "--to", "png", "--display", "no such display",
                 "-o", str(tmp_path / "x.png"), "-q"]) == 2


def test_warp_writes_the_display_codes(tmp_path):
    from lenslab.lenses import Camera
    from lenslab.warp import warp

    img = (np.random.default_rng(2).random((32, 64, 3)) * 8).astype(np.float32)
    lio.write(tmp_path / "pano.exr", img, pixel_type="float")
    assert main(["warp", str(tmp_path / "pano.exr"), "-o", str(tmp_path / "f.png"), "--to", "fisheye:fov=180",
                 "--size", "32x32", "--display", "srgb", "--view", "ACES 2.0 - SDR", "-q"]) == 0
    codes = cv2.imread(str(tmp_path / "f.png"), cv2.IMREAD_UNCHANGED)
    warped, alpha = warp(img, Camera.from_spec("equirect", (64, 32)), Camera.from_spec("fisheye:fov=180", (32, 32)))
    inside = codes[..., 3] == 255
    assert inside.sum() > 500 and (alpha[inside] == 1).all()
    want = np.clip(_reference(warped, *SDR), 0, 1).astype(np.float64) * 255
    got = codes[..., 2::-1].astype(np.float64)
    assert np.abs(got - want)[inside].max() <= 0.5 + 255 * 1e-5  # rounding to the nearest 8-bit code


def test_tonemap_writes_the_display_codes(tmp_path):
    img = _scene()
    lio.write(tmp_path / "s.exr", img, pixel_type="float")
    assert main(["tonemap", str(tmp_path / "s.exr"), "--bits", "16", "--display", "srgb", "--view", "ACES 2.0 - SDR",
                 "--exposure", "1", "-o", str(tmp_path / "s.png"), "-q"]) == 0
    codes = cv2.imread(str(tmp_path / "s.png"), cv2.IMREAD_UNCHANGED)[..., ::-1].astype(np.float64)
    want = np.clip(_reference(img * 2.0, *SDR), 0, 1).astype(np.float64) * 65535  # --exposure 1: twice the light
    assert np.abs(codes - want).max() <= 0.5 + 65535 * 1e-5  # rounding to the nearest code, plus 1e-5 of OCIO
    # several inputs into a folder go through the same transform
    lio.write(tmp_path / "t.exr", img, pixel_type="float")
    assert main(["tonemap", str(tmp_path / "s.exr"), str(tmp_path / "t.exr"), "--bits", "16", "--display", "srgb",
                 "--view", "ACES 2.0 - SDR", "--exposure", "1", "-o", str(tmp_path / "out"), "-q"]) == 0
    batch = cv2.imread(str(tmp_path / "out" / "t.png"), cv2.IMREAD_UNCHANGED)[..., ::-1].astype(np.float64)
    assert np.abs(batch - want).max() <= 0.5 + 65535 * 1e-5
    # bad names are one usage error; --view without --display too; PQ needs 16 bits (refused before any work)
    assert main(["tonemap", str(tmp_path / "s.exr"), "--display", "no such display", "-o", str(tmp_path / "x.png")]) == 2
    assert main(["tonemap", str(tmp_path / "s.exr"), "--view", "ACES 2.0 - SDR", "-o", str(tmp_path / "x.png")]) == 2
    assert main(["tonemap", str(tmp_path / "s.exr"), "--display", "rec.2100-pq", "-o", str(tmp_path / "x.jpg")]) == 2
    assert not (tmp_path / "x.png").exists() and not (tmp_path / "x.jpg").exists()
