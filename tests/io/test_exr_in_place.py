"""A half-float EXR made in the image's own memory (``in_place``: what ``lenslab convert`` does with the
image it read, so that a conversion needs no second copy) holds exactly what a copy would: NumPy's IEEE
float32 -> float16 cast, with finite values beyond half's range clamped to +-65504 (infinities and NaN
kept), as OpenImageIO reads it back."""

from __future__ import annotations

import subprocess
import sys
import warnings

import numpy as np
import pytest

import lenslab.io as lio
from lenslab.io.halves import to_half

oiio = pytest.importorskip("OpenImageIO")

HALF_MAX = 65504.0  # the largest finite IEEE 754 binary16 value


def _image(h=37, w=29, c=3, seed=3):
    rng = np.random.default_rng(seed)
    img = (rng.standard_normal((h, w, c)) * 10.0 ** rng.uniform(-8, 6, (h, w, c))).astype(np.float32)
    img.flat[:6] = [np.inf, -np.inf, np.nan, 1e9, -7e4, 65519.0]  # 65519 rounds to inf in IEEE: clamped
    return img


def _expected(img):
    """The float16 cast of IEEE 754 (NumPy), after clamping finite values beyond half's range."""
    big = np.isfinite(img) & (np.abs(img) > HALF_MAX)
    return np.where(big, np.copysign(np.float32(HALF_MAX), img), img).astype(np.float16)


@pytest.mark.parametrize("rows", [1, 5, 256])
def test_in_place_half_equals_the_ieee_cast(rows):
    img = _image()
    expected = _expected(img)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        out = to_half(img, rows=rows, in_place=True)
    assert out.dtype == np.float16 and out.shape == img.shape
    assert np.shares_memory(out, img)  # no allocation of the image's size
    np.testing.assert_array_equal(out.view(np.uint16), expected.view(np.uint16))  # bit for bit, NaN included


def test_an_array_that_is_not_its_own_contiguous_float32_is_copied():
    img = _image(c=4)
    view = img[..., :3]  # not contiguous: converted into a new array, the source untouched
    before = img.copy()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        out = to_half(view, in_place=True)
    assert not np.shares_memory(out, img)
    np.testing.assert_array_equal(img.view(np.uint32), before.view(np.uint32))
    np.testing.assert_array_equal(out.view(np.uint16), _expected(view).view(np.uint16))


def test_written_in_place_oiio_reads_the_half_cast(tmp_path):
    img = np.abs(_image())
    img.flat[:6] = [0.5, 1e9, 3.0, 7.25, 1e-3, 65519.0]
    expected = _expected(img).astype(np.float64)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        lio.write(tmp_path / "a.exr", img, in_place=True)
    inp = oiio.ImageInput.open(str(tmp_path / "a.exr"))
    spec = inp.spec()
    got = np.asarray(inp.read_image("float"), np.float64).reshape(spec.height, spec.width, spec.nchannels)
    inp.close()
    assert spec.format == oiio.HALF
    np.testing.assert_array_equal(got, expected)


def test_convert_with_exposure_writes_the_scaled_half_and_leaves_the_input(tmp_path):
    img = np.abs(_image(h=64, w=48)).clip(0, 1000).astype(np.float32)
    src = tmp_path / "in.pfm"
    lio.write(src, img)
    before = src.read_bytes()
    out = tmp_path / "out.exr"
    run = subprocess.run([sys.executable, "-m", "lenslab", "convert", str(src), "--to", "exr", "-o", str(out),
                          "--exposure", "1", "-q"], capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    assert src.read_bytes() == before
    inp = oiio.ImageInput.open(str(out))
    spec = inp.spec()
    got = np.asarray(inp.read_image("float"), np.float64).reshape(spec.height, spec.width, spec.nchannels)
    inp.close()
    # one stop is an exact doubling in float32; the file holds its IEEE half cast
    np.testing.assert_array_equal(got, (img * np.float32(2.0)).astype(np.float16).astype(np.float64))


def test_exposure_in_place_copies_an_array_it_may_not_write():
    from lenslab.io.alpha import expose

    img = np.arange(24, dtype=np.float32).reshape(2, 4, 3)
    img.flags.writeable = False  # a reader's view of its buffer
    out = expose(img, 1.0, in_place=True)
    assert not np.shares_memory(out, img)
    np.testing.assert_array_equal(out, np.arange(24, dtype=np.float32).reshape(2, 4, 3) * 2)  # one stop: x 2
    own = np.ones((2, 2, 4), np.float32) * 0.5
    assert expose(own, -1.0, in_place=True) is own
    np.testing.assert_array_equal(own, [[[0.25, 0.25, 0.25, 0.5]] * 2] * 2)  # alpha kept
