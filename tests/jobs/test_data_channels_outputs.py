"""Two or four channels that are data (an EXR's ``u, v``: only ``A`` is alpha) never become alpha by their
count in an output: EXR keeps them by name (OpenEXR's reading of the output holds the input's values),
formats and tone curves that would take the last for alpha refuse them in one line; a real grey+alpha EXR
still goes to PNG (OpenImageIO reads ``Y, A``)."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

OpenEXR = pytest.importorskip("OpenEXR")


def _exr(path, chans):
    OpenEXR.File({"type": OpenEXR.scanlineimage, "compression": OpenEXR.ZIP_COMPRESSION}, dict(chans)).write(str(path))
    return path


def _run(*args):
    return subprocess.run([sys.executable, "-m", "lenslab", *map(str, args)], capture_output=True, text=True)


@pytest.fixture
def uv(tmp_path):
    rng = np.random.default_rng(2)
    chans = {"u": rng.uniform(-3, 3, (6, 8)).astype(np.float32), "v": rng.uniform(0, 9, (6, 8)).astype(np.float32)}
    return _exr(tmp_path / "uv.exr", chans), chans


def test_exr_keeps_two_data_channels(uv, tmp_path):
    path, chans = uv
    out = tmp_path / "out.exr"
    run = _run("convert", path, "--to", "exr", "--pixel-type", "float", "-o", out)
    assert run.returncode == 0, run.stderr
    got = OpenEXR.File(str(out), separate_channels=True).parts[0].channels
    assert set(got) == {"u", "v"}
    for name, plane in chans.items():  # v up to 9: never clipped to 1 as an alpha would be
        np.testing.assert_array_equal(got[name].pixels, plane)


@pytest.mark.parametrize("args", [["convert", "--to", "png"], ["convert", "--to", "tiff"], ["convert", "--to", "jpg"],
                                  ["tonemap"], ["warp", "--from", "equirect", "--to", "fisheye", "--size", "8x8"]])
def test_formats_and_curves_that_would_take_v_for_alpha_refuse_in_one_line(uv, tmp_path, args):
    path, _ = uv
    ext = {"tiff": "tif", "jpg": "jpg"}.get(args[2] if args[0] == "convert" else "png", "png")
    out = tmp_path / f"out.{ext}"
    run = _run(args[0], path, *args[1:], "-o", out)
    assert run.returncode == 1 and not out.exists()
    lines = run.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"lenslab {args[0]}: error: {path}: channels u, v hold data")


def test_a_grey_and_alpha_exr_still_goes_to_png(tmp_path):
    oiio = pytest.importorskip("OpenImageIO")
    y = np.full((4, 5), 0.25, np.float32)
    a = np.full((4, 5), 0.5, np.float32)
    path = _exr(tmp_path / "ya.exr", {"Y": y, "A": a})
    out = tmp_path / "ya.png"
    assert _run("convert", path, "--to", "png", "-o", out).returncode == 0
    spec = oiio.ImageInput.open(str(out)).spec()
    assert spec.nchannels == 2 and tuple(spec.channelnames) == ("Y", "A")
