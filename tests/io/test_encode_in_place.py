"""Display files encoded in the image's own memory (``in_place=True``: what ``lenslab tonemap`` and
``lenslab convert`` do with the image they read, so that encoding holds no second array of its size)
hold the codes of colour-science's sRGB inverse EOTF of the straight colour, rounded, and alpha as
coverage, as OpenImageIO reads them back; the same codes as a copy gives, dither included. Exact
equality: the codes are integers and each value is far from a rounding tie (random float32 values)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import lenslab.io as lio
from lenslab.io.encode import _BLOCK, NonFiniteWarning, encode_codes
from tests.io.test_encode_blocks import _image, check_straight_codes

pytest.importorskip("OpenImageIO")
pytest.importorskip("colour")


@pytest.mark.parametrize("bits,c", [(8, 4), (16, 4), (8, 3), (16, 2)])
def test_codes_made_in_place_share_the_image_memory_and_equal_a_copy(bits, c):
    rng = np.random.default_rng(11)
    img = _image(rng, 311, 273, c)
    assert img.size > 2 * _BLOCK  # several blocks: each block's codes land over floats already read
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NonFiniteWarning)
        expected = encode_codes(img.copy(), bits, straight=True, dither=True)
        given = img.copy()
        got = encode_codes(given, bits, straight=True, dither=True, in_place=True)
    assert np.shares_memory(got, given) and got.shape == img.shape
    assert np.array_equal(got, expected)


@pytest.mark.parametrize("ext,bits", [(".png", 8), (".png", 16), (".jpg", 8)])
def test_a_file_written_in_place_holds_colour_science_srgb(tmp_path, ext, bits):
    rng = np.random.default_rng(7)
    img = _image(rng, 301, 257, 4 if ext == ".png" else 3)
    if ext == ".jpg":
        img = np.abs(np.nan_to_num(img, nan=0.5, posinf=1.0, neginf=0.0))
    given = img.copy()
    path = tmp_path / f"out{ext}"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NonFiniteWarning)
        lio.write(path, given, in_place=True, **({"bits": bits} if ext == ".png" else {"quality": 100}))
    assert not np.array_equal(given, img, equal_nan=True)  # the image's memory took the codes
    if ext == ".png":
        check_straight_codes(path, img, bits)
    else:  # JPEG is lossy: the file written in place is byte for byte the one a copy gives
        other = tmp_path / "copy.jpg"
        lio.write(other, img, quality=100)
        assert path.read_bytes() == other.read_bytes()
