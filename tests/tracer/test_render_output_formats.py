"""``tracer render -o`` writes every HDR format its help names: EXR keeps the camera, PFM, TIFF and Radiance HDR
hold the same pixels without it. A name no format has, or a display format for the linear variance, is a usage
error (exit 2, one line) found before the render starts, so nothing is written. The pixels are read back by
OpenImageIO, or for PFM by the format's definition transcribed here, never by lenslab."""

from __future__ import annotations

import numpy as np
import pytest

from tracer.cli import main

oiio = pytest.importorskip("OpenImageIO")

ARGS = ["render", "--scene", "furnace", "--camera", "perspective:fov=60", "--size", "8x6", "--spp", "1", "-q"]


def oiio_pixels(path) -> np.ndarray:
    inp = oiio.ImageInput.open(str(path), oiio.ImageSpec())
    assert inp is not None, oiio.geterror()
    spec = inp.spec()
    pixels = np.asarray(inp.read_image("float")).reshape(spec.height, spec.width, spec.nchannels)
    inp.close()
    return pixels


def pfm_pixels(path) -> np.ndarray:
    """PFM as Debevec defines it: 'PF', width height, scale (negative: little-endian), then float32 RGB rows
    from the bottom row up."""
    magic, size, scale, raster = path.read_bytes().split(b"\n", 3)
    assert magic == b"PF"
    w, h = map(int, size.split())
    order = "<" if float(scale) < 0 else ">"
    return np.frombuffer(raster, f"{order}f4").reshape(h, w, 3)[::-1]


@pytest.mark.parametrize("ext", [".pfm", ".tif"])
def test_float_formats_hold_the_exr_pixels(tmp_path, ext):
    exr, other = tmp_path / "r.exr", tmp_path / f"r{ext}"
    assert main([*ARGS, "-o", str(exr)]) == 0
    assert main([*ARGS, "-o", str(other)]) == 0
    a, b = oiio_pixels(exr), (pfm_pixels(other) if ext == ".pfm" else oiio_pixels(other))
    assert b.shape == (6, 8, 3)
    # the same seed renders the same float32 radiance; both formats store float32 exactly
    np.testing.assert_array_equal(a[..., :3], b)


def test_radiance_hdr_holds_the_pixels_to_its_precision(tmp_path):
    exr, hdr = tmp_path / "r.exr", tmp_path / "r.hdr"
    assert main([*ARGS, "-o", str(exr)]) == 0
    assert main([*ARGS, "-o", str(hdr)]) == 0
    # RGBE keeps an 8-bit mantissa under a shared exponent: within 1/128 of the largest channel
    a, b = oiio_pixels(exr)[..., :3], oiio_pixels(hdr)
    assert np.all(np.abs(a - b) <= a.max(axis=-1, keepdims=True) / 128 + 1e-7)


@pytest.mark.parametrize("extra", [["-o", "{d}/r.xyz"], ["-o", "{d}/r.exr", "--variance-out", "{d}/v.png"]])
def test_unwritable_names_are_usage_errors_before_the_render(tmp_path, capsys, extra):
    argv = [*ARGS, *(a.format(d=tmp_path) for a in extra)]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("tracer render: error:"), err
    assert list(tmp_path.iterdir()) == []
