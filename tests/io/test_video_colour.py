"""The compiled video colour passes against colour-science's transfer functions and their NumPy references:
16-bit codes to linear light (the same bits as the table lookup), and linear light to 16-bit codes (within the
rounding and the inverse table's interpolation error of colour-science's own inverse, in float64)."""

from __future__ import annotations

from fractions import Fraction

import colour
import numpy as np
import pytest

from lenslab.io.video import VideoInfo
from lenslab.io.video.colour import (codes16_to_linear, codes16_to_linear_compiled, from_linear, linear_to_codes16,
                                     to_linear)

CURVES = {"bt1886": 1, "srgb": 13, "pq": 16}
# colour-science's inverse transfer functions, transcribed here in float64 (1.0 = 203 cd/m2 for PQ, BT.2408)
INVERSE = {"bt1886": lambda x: colour.models.eotf_inverse_BT1886(np.minimum(x, 1.0), L_B=0, L_W=1),
           "srgb": lambda x: colour.cctf_encoding(np.minimum(x, 1.0), "sRGB"),
           "pq": lambda x: colour.models.eotf_inverse_ST2084(x * 203.0)}
BT2020_TO_709 = colour.matrix_RGB_to_RGB(colour.RGB_COLOURSPACES["ITU-R BT.2020"], colour.RGB_COLOURSPACES["ITU-R BT.709"])


def _info(transfer, primaries=1):
    return VideoInfo(8, 8, Fraction(24), 1, "h264", "yuv420p", primaries=primaries, transfer=transfer)


@pytest.mark.parametrize("curve", list(CURVES))
@pytest.mark.parametrize("primaries", [1, 9], ids=["bt709", "bt2020"])
def test_compiled_decoding_is_the_table_lookup(curve, primaries):
    info = _info(CURVES[curve], primaries)
    rng = np.random.default_rng(CURVES[curve] + primaries)
    codes = rng.integers(0, 65536, (67, 45, 3), dtype=np.uint16)
    codes[0, :3] = [[0, 0, 0], [65535, 65535, 65535], [1, 32768, 65534]]
    got = codes16_to_linear_compiled(codes, info)
    want = codes16_to_linear(codes, info)  # NumPy: the table, then the BT.2020 -> Rec.709 matrix in float64
    assert got.dtype == np.float32 and got.shape == codes.shape
    if primaries == 1:
        np.testing.assert_array_equal(got, want)  # one lookup: nothing to round differently
    else:  # the same float64 products summed in another order (or fused), then one rounding to float32
        np.testing.assert_array_max_ulp(got, want, maxulp=1)
    # and the table is colour-science's EOTF of code / 65535 (value by value, float64, then float32)
    np.testing.assert_array_max_ulp(got, to_linear(codes.astype(np.float64) / 65535.0, info), maxulp=1)


def _hostile(rng, top):
    lin = (rng.random((61, 37, 3)) ** 4 * top).astype(np.float32)
    lin[0, :6] = [[np.nan, np.inf, -np.inf], [1e30, -1e30, 0], [1e-30, 1e-12, 1e-7], [0.5, 1, 2],
                  [top, 2 * top, 1e4], [-0.1, 0.18, 1e-3]]
    return lin


@pytest.mark.parametrize("curve", list(CURVES))
@pytest.mark.parametrize("primaries", [1, 9], ids=["bt709", "bt2020"])
def test_compiled_encoding_is_colour_science_within_its_table_error(curve, primaries):
    info = _info(CURVES[curve], primaries)
    lin = _hostile(np.random.default_rng(7 + primaries), 60.0 if curve == "pq" else 1.5)
    got = linear_to_codes16(lin, info)
    assert got.dtype == np.uint16 and got.shape == lin.shape
    # outside value: NaN -> 0, +inf -> 1e4, -inf -> 0, Rec.709 -> BT.2020, colour-science's inverse in float64
    x = np.nan_to_num(lin.astype(np.float64), nan=0.0, posinf=1e4, neginf=0.0)
    if primaries == 9:
        x = x @ np.linalg.inv(BT2020_TO_709).T
    exact = np.clip(INVERSE[curve](np.maximum(x, 0.0)), 0, 1) * 65535.0
    # rounding (0.5 code) plus the table's interpolation error: 1024 knots a binade put the error of linear
    # interpolation of these curves below 1e-6 of the code range (0.066 of a 16-bit code); the matrix result is
    # rounded to float32 first (relative 6e-8, under 0.002 code through these slopes)
    err = np.abs(got - exact)
    assert err.max() <= 0.5 + 0.07, err.max()
    # the NumPy step it replaces differs only where the exact code is that close to a rounding half
    ref = np.round(from_linear(lin, info) * 65535.0).astype(np.int64)
    assert np.abs(got.astype(np.int64) - ref).max() <= 1
    assert (got != ref).mean() < 0.01


def test_display_encoded_values_are_clamped_not_curved():
    lin = np.array([[[np.nan, -1.0, 0.25], [1.5, np.inf, 0.5]]], np.float32)
    got = linear_to_codes16(lin, _info(16, 9), encoded=True)
    np.testing.assert_array_equal(got, [[[0, 0, 16384], [65535, 65535, 32768]]])  # 0.25 * 65535 = 16383.75
