"""An SDR Display P3 written to PNG says so (cICP: colour primaries 12 P3-D65, transfer 13 sRGB, matrix 0,
full range 1: ITU-T H.273 tables 2-4), and a PNG so tagged is read as sRGB codes on P3-D65 primaries,
converted to Rec.709 by colour-science's matrix. sRGB displays stay untagged.

Expected values: H.273's code points written out here, OpenImageIO's reading of the chunk, the chunk bytes
parsed here (PNG Specification, 5.3), PyOpenColorIO's processor, colour-science's sRGB decoding and its
P3-D65 -> BT.709 matrix in float64."""

from __future__ import annotations

import io
import struct
import subprocess
import sys
import zlib

import cv2
import numpy as np
import pytest

PyOpenColorIO = pytest.importorskip("PyOpenColorIO")
oiio = pytest.importorskip("OpenImageIO")
colour = pytest.importorskip("colour")

import lenslab.io as lio  # noqa: E402

P3_TO_709 = colour.matrix_RGB_to_RGB(colour.RGB_COLOURSPACES["P3-D65"], colour.RGB_COLOURSPACES["ITU-R BT.709"])
DISPLAY_P3 = (12, 13, 0, 1)  # H.273: primaries 12 SMPTE EG 432-1, transfer 13 IEC 61966-2-1 (sRGB), RGB, full


def _cicp(data: bytes):
    pos, found = 8, []
    while pos + 8 <= len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        if kind == b"cICP":
            found.append(tuple(data[pos + 8:pos + 12]))
        pos += 12 + n
    return found


def _convert(src, out, display):
    return subprocess.run([sys.executable, "-m", "lenslab", "convert", str(src), "--to", "png", "--display", display,
                           "--view", "Un-tone-mapped", "-o", str(out)], capture_output=True, text=True)


def _ocio_codes(img, display):
    cfg = PyOpenColorIO.Config.CreateFromFile("ocio://default")
    proc = cfg.getProcessor("Linear Rec.709 (sRGB)", display, "Un-tone-mapped", PyOpenColorIO.TRANSFORM_DIR_FORWARD)
    out = np.ascontiguousarray(img, np.float32).copy()
    proc.getDefaultCPUProcessor().applyRGB(out)
    return out


def _scene():
    return np.array([[[0.18, 0.18, 0.18], [0.9, 0.2, 0.05], [0.1, 0.6, 0.2], [0.02, 0.05, 0.7]]], np.float32)


def test_display_p3_code_points():
    from lenslab.io.colour.png_cicp import display_code_points

    assert display_code_points("Display P3 - Display") == DISPLAY_P3
    assert display_code_points("sRGB - Display") is None  # Rec.709 primaries, sRGB: what readers assume


def test_a_display_p3_png_is_tagged_and_reads_back_as_the_scene(tmp_path):
    img = _scene()
    lio.write(tmp_path / "s.exr", img, pixel_type="float")
    out = tmp_path / "p3.png"
    run = _convert(tmp_path / "s.exr", out, "Display P3 - Display")
    assert run.returncode == 0, run.stderr
    assert _cicp(out.read_bytes()) == [DISPLAY_P3]
    inp = oiio.ImageInput.open(str(out))
    spec = inp.spec()
    inp.close()
    assert tuple(spec.getattribute("CICP")) == DISPLAY_P3  # OpenImageIO reads the chunk as H.273 says
    assert "p3d65" in spec.getattribute("oiio:ColorSpace")  # and takes the codes for P3-D65, not sRGB
    codes = cv2.cvtColor(cv2.imread(str(out), cv2.IMREAD_UNCHANGED), cv2.COLOR_BGR2RGB).astype(np.float64) / 255
    # the 8-bit codes are OpenColorIO's for the display, rounded
    np.testing.assert_allclose(codes, _ocio_codes(img, "Display P3 - Display"), rtol=0, atol=0.5 / 255 + 1e-6)
    back, meta = lio.read(out)
    want = colour.cctf_decoding(codes, "sRGB") @ P3_TO_709.T
    np.testing.assert_allclose(back, want, rtol=1e-5, atol=1e-6)  # float32 of the float64 formula
    # and the scene comes back: 8-bit sRGB codes step by up to 1.3 % of a value near 0.02
    np.testing.assert_allclose(back, img, rtol=0.015, atol=1.5e-3)
    assert "P3-D65" in meta["attributes"]["note"]


def test_an_srgb_display_png_has_no_chunk(tmp_path):
    lio.write(tmp_path / "s.exr", _scene(), pixel_type="float")
    out = tmp_path / "srgb.png"
    run = _convert(tmp_path / "s.exr", out, "sRGB - Display")
    assert run.returncode == 0, run.stderr
    assert _cicp(out.read_bytes()) == []


def test_a_png_tagged_srgb_p3_is_read_into_rec709(tmp_path):
    rng = np.random.default_rng(3)
    codes = rng.integers(0, 256, size=(5, 7, 4), dtype=np.uint8)
    codes[..., 3] = 255  # opaque: straight and premultiplied colour agree
    codes[0, 0, 3] = 128  # one half-covered pixel: premultiplied after the conversion
    ok, buf = cv2.imencode(".png", cv2.cvtColor(codes, cv2.COLOR_RGBA2BGRA))
    assert ok
    png = buf.tobytes()
    body = b"cICP" + bytes(DISPLAY_P3)
    chunk = struct.pack(">I", 4) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)
    (tmp_path / "p3.png").write_bytes(png[:33] + chunk + png[33:])
    got, _ = lio.read(tmp_path / "p3.png")
    a = codes[..., 3:] / 255.0
    want = (colour.cctf_decoding(codes[..., :3] / 255.0, "sRGB") @ P3_TO_709.T) * a
    np.testing.assert_allclose(got[..., :3], want, rtol=1e-5, atol=1e-6)  # float32 of the float64 formula
    np.testing.assert_allclose(got[..., 3:], a, rtol=0, atol=1e-7)
    raw, _ = lio.read(tmp_path / "p3.png", raw=True)  # raw: the codes as they are
    np.testing.assert_allclose(raw[..., :3], codes[..., :3] / 255.0, rtol=0, atol=1e-7)


def test_a_display_p3_jpeg_carries_its_profile_and_a_ppm_says_it_has_no_tag(tmp_path):
    from PIL import Image, ImageCms

    lio.write(tmp_path / "s.exr", _scene(), pixel_type="float")
    run = subprocess.run([sys.executable, "-m", "lenslab", "convert", str(tmp_path / "s.exr"), "--to", "jpg",
                          "--display", "Display P3 - Display", "-o", str(tmp_path / "p3.jpg")],
                         capture_output=True, text=True)
    assert run.returncode == 0 and "no tag" not in run.stderr, run.stderr
    with Image.open(tmp_path / "p3.jpg") as im:  # Pillow finds the profile in its APP2 segments
        icc = im.info["icc_profile"]
    assert ImageCms.getProfileDescription(ImageCms.ImageCmsProfile(io.BytesIO(icc))).strip() == "Display P3"
    run = subprocess.run([sys.executable, "-m", "lenslab", "convert", str(tmp_path / "s.exr"), "--to", "ppm",
                          "--display", "Display P3 - Display", "-o", str(tmp_path / "p3.ppm")],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    notes = [line for line in run.stderr.splitlines() if "no tag for these primaries" in line]
    assert len(notes) == 1 and "write PNG" in notes[0]
    srgb = subprocess.run([sys.executable, "-m", "lenslab", "convert", str(tmp_path / "s.exr"), "--to", "jpg",
                           "--display", "sRGB - Display", "-o", str(tmp_path / "srgb.jpg")], capture_output=True, text=True)
    assert srgb.returncode == 0 and "no tag" not in srgb.stderr
