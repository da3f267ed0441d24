"""Half floats are one stage (:mod:`lenslab.io.halves`) for every writer: a half TIFF and a half EXR hold the same
bits, read back by libraries other than lenslab's own codecs (tifffile for the TIFF, OpenImageIO for the EXR).

Expected values are NumPy's: ``np.clip(x, -65504, 65504).astype(np.float16)`` (65504 is the largest finite IEEE 754
binary16 value), bit for bit, on finite data with ties between neighbouring halves, subnormals and values beyond
half's range; infinities and NaN are kept (as the EXR writer has always documented), so they are checked apart from
the clip. Each write that clamps gives one note naming the count and the format. No tolerance: the cast is exact.
"""

from __future__ import annotations

import contextlib
import io
import warnings

import numpy as np
import pytest

import lenslab.io as lio
from lenslab.io.halves import HalfOverflowWarning

tifffile = pytest.importorskip("tifffile")
oiio = pytest.importorskip("OpenImageIO")

HALF_MAX = 65504.0  # the largest finite IEEE 754 binary16 value


def _finite_image() -> np.ndarray:
    """64 x 96 x 3 float32: random halves, the midpoints between neighbours (ties to even), one float32 step
    either side of them, subnormal halves and values beyond +-65504 up to 3e38, both signs."""
    rng = np.random.default_rng(11)
    bits = rng.integers(0, 0x7bff, 4000, dtype=np.uint16)  # finite halves below the largest
    lo = bits.view(np.float16).astype(np.float64)
    hi = (bits + 1).view(np.float16).astype(np.float64)
    ties = ((lo + hi) / 2).astype(np.float32)  # exact in float32
    sub = rng.integers(0, 0x400, 2000, dtype=np.uint16).view(np.float16).astype(np.float32)  # subnormal halves
    subties = (sub + np.float32(2.0 ** -25)).astype(np.float32)
    big = (10.0 ** rng.uniform(4.82, 38.5, 1500)).astype(np.float32)  # 65500 .. 3e38
    edge = np.array([65504, 65519.99, 65520, 65536, 1e5, 2.0 ** -24, 2.0 ** -25, 1e-45, 0.0], np.float32)
    x = np.concatenate([ties, np.nextafter(ties, np.float32(np.inf)), np.nextafter(ties, np.float32(0)), sub,
                        subties, big, edge, rng.standard_normal(5000).astype(np.float32) * 1e3])
    x = np.concatenate([x, -x])
    x = np.resize(x, 64 * 96 * 3)
    rng.shuffle(x)
    assert np.isfinite(x).all()
    return x.reshape(64, 96, 3)


def _write(path, image, **options) -> list:
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        lio.write(path, image, **options)
    return [w for w in said if issubclass(w.category, HalfOverflowWarning)]


def _exr_halves(path) -> np.ndarray:
    buf = oiio.ImageBuf(str(path))
    assert buf.spec().format == oiio.HALF
    return np.asarray(buf.get_pixels(oiio.HALF)).view(np.uint16)


@pytest.mark.parametrize("in_place", [False, True])
def test_tiff_and_exr_hold_numpys_clipped_cast(tmp_path, in_place):
    image = _finite_image()
    want = np.clip(image, -HALF_MAX, HALF_MAX).astype(np.float16).view(np.uint16)
    count = int(np.count_nonzero(np.abs(image) > HALF_MAX))
    tif_notes = _write(tmp_path / "h.tif", image.copy(), sample_type="half", in_place=in_place)
    exr_notes = _write(tmp_path / "h.exr", image.copy(), pixel_type="half", in_place=in_place)
    tif = tifffile.imread(tmp_path / "h.tif")
    assert tif.dtype == np.float16
    np.testing.assert_array_equal(tif.view(np.uint16), want)
    np.testing.assert_array_equal(_exr_halves(tmp_path / "h.exr"), want)
    for notes, fmt, option in ((tif_notes, "TIFF", "sample_type"), (exr_notes, "EXR", "pixel_type")):
        assert len(notes) == 1, [str(n.message) for n in notes]
        text = str(notes[0].message)
        assert text.startswith(f"{count} value(s) beyond half's range were clamped to +-65504 in the half {fmt}")
        assert f"{option}='float'" in text


def test_infinities_and_nan_are_kept_in_both(tmp_path):
    image = np.array([[[np.inf, -np.inf, np.nan], [1e5, -1e5, 1.0]]], np.float32)
    for name, options in (("k.tif", {"sample_type": "half"}), ("k.exr", {"pixel_type": "half"})):
        notes = _write(tmp_path / name, image.copy(), **options)
        assert len(notes) == 1 and str(notes[0].message).startswith("2 value(s)")  # the infinities are not counted
    tif = tifffile.imread(tmp_path / "k.tif").astype(np.float32)
    exr = np.asarray(oiio.ImageBuf(str(tmp_path / "k.exr")).get_pixels(oiio.FLOAT))
    for got in (tif, exr):
        assert got[0, 0, 0] == np.inf and got[0, 0, 1] == -np.inf and np.isnan(got[0, 0, 2])
        assert got[0, 1].tolist() == [65504.0, -65504.0, 1.0]


@pytest.mark.parametrize("command", ["convert", "warp"])
def test_commands_clamp_a_half_tiff_with_one_note(tmp_path, command):
    from lenslab.cli.main import main

    image = np.full((16, 32, 3), 1e5, np.float32)
    image[..., 1] = -1e5
    image[..., 2] = 0.5
    lio.write(tmp_path / "in.exr", image, pixel_type="float")
    out = tmp_path / "out.tif"
    args = [command, str(tmp_path / "in.exr"), "-o", str(out), "--pixel-type", "half"]
    if command == "warp":
        args += ["--to", "equirect", "--size", "8x4", "--no-alpha"]
    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        assert main(args) == 0
    got = tifffile.imread(out)
    assert got.dtype == np.float16 and got.shape[2] == 3
    assert np.all(got[..., 0] == 65504) and np.all(got[..., 1] == -65504) and np.all(got[..., 2] == 0.5)
    count = 2 * got.shape[0] * got.shape[1]
    notes = [line for line in err.getvalue().splitlines() if "beyond half's range" in line]
    assert len(notes) == 1, err.getvalue()
    assert f"{count} value(s) beyond half's range were clamped to +-65504 in the half TIFF" in notes[0]
    assert "--pixel-type float" in notes[0]
