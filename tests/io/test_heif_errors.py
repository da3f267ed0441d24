"""HEIC files are recognised by their ftyp brands, not their names; damaged, truncated and tiny files give one
line and exit code 1; without pillow-heif the line names the extra to install; commands start without
importing it; ``convert`` and ``warp`` take a HEIC end to end.

Expected values: the brands of ISO/IEC 23008-12 (``heic``, ``heix``, ``mif1``...) and ISO/IEC 14496-12's
``ftyp`` layout written byte by byte here; for the end-to-end runs, OpenEXR's reading of the EXR written and
colour-science's sRGB curve on pillow-heif's decoded codes (float32 rounding: 1e-6)."""

from __future__ import annotations

import struct
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

pillow_heif = pytest.importorskip("pillow_heif")
colour = pytest.importorskip("colour")

import lenslab.io as lio  # noqa: E402
from lenslab.cli.main import main  # noqa: E402
from lenslab.io.registry import sniff, sniff_bytes  # noqa: E402


def _heic(path, codes=None, quality=-1) -> Path:
    codes = np.random.default_rng(0).integers(0, 256, (32, 64, 3), dtype=np.uint8) if codes is None else codes
    h, w, _ = codes.shape
    pillow_heif.from_bytes("RGB", (w, h), codes.tobytes()).save(str(path), quality=quality, chroma=444)
    return Path(path)


def _ftyp(major: bytes, *compatible: bytes) -> bytes:
    body = major + b"\x00\x00\x00\x00" + b"".join(compatible)
    return struct.pack(">I", 8 + len(body)) + b"ftyp" + body


@pytest.mark.parametrize("major,compatible", [(b"heic", (b"mif1", b"heic")), (b"heix", (b"mif1", b"heix")),
                                              (b"mif1", (b"mif1", b"heic")), (b"msf1", (b"mif1", b"msf1", b"hevc")),
                                              (b"hevc", (b"mif1", b"heic", b"hevc"))])  # (a still beside a sequence)
def test_heif_brands_are_recognised(major, compatible):
    assert sniff_bytes((_ftyp(major, *compatible) + bytes(32))[:32]) == "heif"


@pytest.mark.parametrize("major,compatible,want", [(b"isom", (b"isom", b"mp41"), "video"),
                                                   (b"qt  ", (b"qt  ",), "video"),
                                                   (b"avif", (b"mif1", b"avif"), "video"),
                                                   (b"mif1", (b"mif1", b"avif"), "video")])
def test_other_iso_media_files_are_not_heif(major, compatible, want):
    assert sniff_bytes((_ftyp(major, *compatible) + bytes(32))[:32]) == want


def test_a_heic_is_known_by_its_bytes_and_a_heic_name_proves_nothing(tmp_path):
    path = _heic(tmp_path / "photo.heic")
    renamed = path.rename(tmp_path / "photo.png")
    assert sniff(renamed) == "heif" and lio.read(renamed)[1]["format"] == "heif"
    png = tmp_path / "really-a-png.heic"
    lio.write(tmp_path / "x.png", np.zeros((4, 4, 3), np.float32)).rename(png)
    assert sniff(png) == "png"
    text = tmp_path / "notes.heic"
    text.write_text("not an image at all\n")
    with pytest.raises(lio.FormatError, match="not a recognised image"):
        lio.read(text)


def _one_line_failure(capsys, argv) -> str:
    assert main(argv) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    return err[0]


def test_truncated_and_tiny_files_fail_in_one_line(tmp_path, capsys):
    data = _heic(tmp_path / "whole.heic", quality=80).read_bytes()
    for n in (300, len(data) // 2, len(data) - 1):  # the header cut, the HEVC data cut, the last byte gone
        cut = tmp_path / f"cut{n}.heic"
        cut.write_bytes(data[:n])
        line = _one_line_failure(capsys, ["convert", str(cut), "-o", str(tmp_path / f"cut{n}.exr"), "-q"])
        assert f"cut{n}.heic" in line and ("truncated" in line or "damaged" in line), line
        assert not (tmp_path / f"cut{n}.exr").exists()
    junk = tmp_path / "junk.heic"  # 300 bytes: a HEIC's ftyp box, then noise
    junk.write_bytes((_ftyp(b"heic", b"mif1", b"heic") + np.random.default_rng(1).bytes(300))[:300])
    assert junk.stat().st_size == 300
    line = _one_line_failure(capsys, ["info", str(junk)])
    assert "junk.heic" in line and "libheif cannot read it" in line


def test_without_pillow_heif_the_line_names_the_extra(tmp_path, capsys, monkeypatch):
    path = _heic(tmp_path / "photo.heic")
    monkeypatch.setitem(sys.modules, "pillow_heif", None)  # import pillow_heif raises ImportError
    line = _one_line_failure(capsys, ["convert", str(path), "-o", str(tmp_path / "out.exr"), "-q"])
    assert "photo.heic" in line and "pip install 'lenslab[heif]'" in line


def test_commands_start_without_importing_pillow_heif(tmp_path):
    path = _heic(tmp_path / "photo.heic")
    code = ("import sys\nfrom lenslab.cli.main import main\nfrom lenslab.io import sniff\n"
            "try:\n    main(['--help'])\nexcept SystemExit:\n    pass\n"
            f"assert sniff({str(path)!r}) == 'heif'\n"
            "print('pillow_heif' in sys.modules)\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip().splitlines()[-1] == "False"


def test_convert_and_warp_take_a_heic(tmp_path):
    import OpenEXR

    flat = np.empty((32, 64, 3), np.uint8)
    flat[...] = (200, 100, 50)
    path = _heic(tmp_path / "pano.heic", flat)
    codes = np.asarray(pillow_heif.open_heif(str(path))).astype(np.float64)
    want = colour.models.eotf_sRGB(codes / 255.0)
    run = lambda *a: subprocess.run([sys.executable, "-m", "lenslab", *map(str, a)],  # noqa: E731
                                    capture_output=True, text=True)
    done = run("convert", path, "-o", tmp_path / "pano.exr", "-q")
    assert done.returncode == 0, done.stderr
    with OpenEXR.File(str(tmp_path / "pano.exr")) as exr:
        got = np.asarray(exr.channels()["RGB"].pixels, np.float64)
    np.testing.assert_allclose(got, want, rtol=1e-3)  # half floats: 11 significant bits
    done = run("warp", path, "-o", tmp_path / "view.exr", "--to", "perspective:fov=90", "--size", "16x16", "-q")
    assert done.returncode == 0, done.stderr
    with OpenEXR.File(str(tmp_path / "view.exr")) as exr:
        view = exr.channels()
        rgb = np.asarray(view["RGB"].pixels if "RGB" in view else view["RGBA"].pixels[..., :3], np.float64)
    # a flat panorama looks flat in every direction: each output pixel is its colour (half floats)
    np.testing.assert_allclose(rgb, np.broadcast_to(want.mean(axis=(0, 1)), rgb.shape), rtol=2e-3)


def test_a_selector_on_a_format_without_images_to_pick_names_the_formats_that_take_one(tmp_path):
    pfm = lio.write(tmp_path / "a.pfm", np.zeros((2, 2, 3), np.float32))
    with pytest.raises(lio.FormatError, match="only applies to EXR, HEIF and JPG files"):
        lio.read(f"{pfm}:1")
