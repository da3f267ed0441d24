"""ICC profiles in the files photographers have: a CMYK JPEG, a damaged profile, a TIFF's profile in
``lenslab info``, and ``--exposure auto`` with a display transform.

Expected values from outside lenslab: Pillow's decoding of the CMYK JPEG (its inks C, M, Y, K as libjpeg gives
them) through the formula ``(255 - C) (255 - K) / 255`` the note states, in float64; littleCMS (Pillow's
``ImageCms``) for what a TIFF's ROMM profile does. Tolerance against the CMYK formula: 2.5 codes of 8 bits,
since the decoder rounds the product to a code (0.5) and the JPEG's CMYK to RGB runs in integer arithmetic on
codes that were themselves rounded (Pillow's and OpenCV's libjpeg builds measured 1.9 apart at most).
"""

from __future__ import annotations

import io
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

colour = pytest.importorskip("colour")
ImageCms = pytest.importorskip("PIL.ImageCms")
from PIL import Image  # noqa: E402

import lenslab.io as lio  # noqa: E402
from lenslab.errors import FormatError  # noqa: E402

GHOSTSCRIPT = Path("/usr/share/color/icc/ghostscript")  # Debian's libgs-common


def _system(name: str) -> bytes:
    path = GHOSTSCRIPT / name
    if not path.is_file():
        pytest.skip(f"{path} is absent (Debian's libgs-common, which .ci/run installs)")
    return path.read_bytes()


def _codes(seed=0) -> np.ndarray:
    return np.random.default_rng(seed).integers(0, 256, (40, 56, 4), dtype=np.uint8)


def _lenslab(*args, cwd) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "lenslab", *args], cwd=cwd, capture_output=True, text=True)


def test_cmyk_jpeg_note_says_what_was_done_and_it_is_true(tmp_path):
    path = tmp_path / "print.jpg"
    Image.frombytes("CMYK", (56, 40), _codes().tobytes()).save(path, quality=100, icc_profile=_system("default_cmyk.icc"))
    inks = np.asarray(Image.open(path), np.float64)  # Pillow's decoding of the file's CMYK
    expected = (255 - inks[..., :3]) * (255 - inks[..., 3:]) / 255
    img, meta = lio.read(path)
    note = meta["attributes"]["icc"]
    assert "CMYK inks" in note and "not applied" in note and "the image is RGB" not in note
    got = colour.cctf_encoding(np.clip(img.astype(np.float64), 0, 1), "sRGB") * 255
    assert np.abs(got - expected).max() <= 2.5


@pytest.mark.parametrize("ext", ["png", "jpg"])
def test_damaged_profile_is_one_line_and_the_decoder_does_not_warn(tmp_path, ext):
    icc = bytearray(_system("a98.icc"))
    icc[128:132] = b"\xff\xff\xff\xff"  # the tag count: far more tags than the profile's bytes hold
    path = tmp_path / f"damaged.{ext}"
    Image.fromarray(_codes()[..., :3]).save(path, icc_profile=bytes(icc))
    with pytest.raises(FormatError, match="declares 4294967295 tags"):
        lio.read(path)
    done = _lenslab("info", str(path), cwd=tmp_path)
    assert done.returncode == 1
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and "declares 4294967295 tags" in lines[0], done.stderr


def test_info_shows_what_a_tiff_profile_did(tmp_path):
    path = tmp_path / "romm.tif"
    Image.fromarray(_codes()[..., :3]).save(path, icc_profile=_system("rommrgb.icc"))
    done = _lenslab("info", str(path), cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert "icc: ICC profile 'Artifex Software ROMMRGB ICC': its curves and colorants applied" in done.stdout
    # and what it did is littleCMS's answer (1 code: littleCMS's 8-bit rounding, as test_icc_profiles states)
    im = Image.open(path)
    srgb = ImageCms.createProfile("sRGB")
    ref = np.asarray(ImageCms.profileToProfile(im, ImageCms.ImageCmsProfile(io.BytesIO(im.info["icc_profile"])),
                                               srgb, outputMode="RGB"), np.float64)
    img, _ = lio.read(path)
    got = colour.cctf_encoding(np.clip(img.astype(np.float64), 0, 1), "sRGB") * 255
    assert np.abs(got - ref).max() <= 1.0


@pytest.mark.parametrize("command", [["tonemap"], ["convert", "--to", "png"], ["warp", "--to", "fisheye"]])
def test_auto_exposure_with_a_display_is_a_usage_error(tmp_path, command):
    pytest.importorskip("PyOpenColorIO")
    src = tmp_path / "in.pfm"
    lio.write(src, np.full((8, 16, 3), 0.5, np.float32))
    done = _lenslab(command[0], str(src), *command[1:], "-o", str(tmp_path / "out.png"),
                    "--display", "Display P3 - Display", "--exposure", "auto", cwd=tmp_path)
    assert done.returncode == 2, done.stderr
    assert done.stderr.strip().count("\n") == 0 and "--exposure auto goes with a tone curve" in done.stderr
    assert not (tmp_path / "out.png").exists()


def test_converting_an_ultra_hdr_jpeg_gives_its_hdr_rendition(tmp_path):
    """The phone's Ultra HDR JPEG (its gain map's XMP namespace, ``hdrgm``, is Adobe's gain-map specification's,
    which Google's Ultra HDR uses): converted to EXR, it is the HDR photo, brighter than SDR white by up to
    2^2.205275 (the file's hdrgm:GainMapMax), with no note; ':sdr' converts the SDR base image."""
    sky = Path(__file__).resolve().parents[3] / "shared" / "data" / "formats" / "oiio-images" / "ultrahdr_sky.jpg"
    if not sky.is_file():
        pytest.skip("../shared/data/formats is absent")
    assert b'hdrgm:GainMapMax="2.205275"' in sky.read_bytes()
    done = _lenslab("convert", str(sky), "--to", "exr", "-o", str(tmp_path / "sky.exr"), cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert not [line for line in done.stderr.splitlines() if "note:" in line and "gain map" in line]
    hdr, _ = lio.read(tmp_path / "sky.exr")
    sdr, _ = lio.read(f"{sky}:sdr")
    assert sdr.max() < 1.05 and 4.0 < hdr.max() <= 2 ** 2.205275 * sdr.max() * 1.001
