"""The float32 -> float16 pass of every half-float writer (EXR, TIFF: ``lenslab.io.halves``), compiled (``to_half``:
F16C where the CPU has it, scalar steps for NaN, values past half's range and the tail), gives NumPy's IEEE 754 cast bit for bit: round to nearest even, subnormal
halves, ties, NaN payloads as NumPy keeps them; finite values beyond +-65504 clamped there and counted (the
expected values: NumPy's ``astype(float16)`` after ``np.clip``-style clamping in the test, and its count of
``isfinite & |x| > 65504``). Its NumPy reference (``to_half_reference``) gives the same.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lenslab.io.halves import HalfOverflowWarning, to_half, to_half_reference

HALF_MAX = 65504.0  # the largest finite IEEE 754 binary16 value


def _expected(x: np.ndarray) -> tuple[np.ndarray, int]:
    big = np.isfinite(x) & (np.abs(x) > HALF_MAX)
    return np.where(big, np.copysign(np.float32(HALF_MAX), x), x).astype(np.float16), int(big.sum())


def _patterns() -> np.ndarray:
    """float32 values at every kind of boundary of the cast: each half and the midpoints between neighbours (ties),
    one float32 step either side, subnormals, both zeros, past the range, infinities, NaN with many payloads."""
    halves = np.arange(0, 0x7c00, dtype=np.uint16).view(np.float16).astype(np.float32)  # every finite half >= 0
    mids = ((halves[:-1].astype(np.float64) + halves[1:]) / 2).astype(np.float32)  # exact in float32: the ties
    near = np.concatenate([mids, halves])
    near = np.concatenate([near, np.nextafter(near, np.float32(np.inf)), np.nextafter(near, np.float32(0))])
    rng = np.random.default_rng(7)
    bits = rng.integers(0, 1 << 32, 200_000, dtype=np.uint64).astype(np.uint32).view(np.float32)  # NaN payloads too
    special = np.array([0.0, -0.0, np.inf, -np.inf, np.nan, 65504, 65519.99, 65520, 1e9, 3.4e38, 2.0 ** -25,
                        2.0 ** -24, 2.0 ** -25 * 1.0000001, 5.96e-8, 1e-45], np.float32)
    x = np.concatenate([near, -near, bits, special])
    return x


@pytest.mark.parametrize("in_place", [False, True])
@pytest.mark.parametrize("tail", [0, 3, 7])
def test_the_compiled_cast_is_numpys_bit_for_bit(in_place, tail):
    x = _patterns()
    x = x[:x.size - (x.size % 8) + tail if tail <= x.size % 8 else x.size]
    want, count = _expected(x)
    src = x.copy()
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        out = to_half(src, in_place=in_place)
    assert np.shares_memory(out, src) == in_place
    np.testing.assert_array_equal(out.view(np.uint16), want.view(np.uint16))
    notes = [w for w in said if issubclass(w.category, HalfOverflowWarning)]
    assert count > 0 and len(notes) == 1 and str(notes[0].message).startswith(f"{count} value(s)")
    ref = np.empty(x.shape, np.float16)
    assert to_half_reference(x, ref) == count
    np.testing.assert_array_equal(ref.view(np.uint16), want.view(np.uint16))


@settings(max_examples=60)
@given(st.lists(st.floats(width=32, allow_nan=True, allow_infinity=True, allow_subnormal=True), min_size=1,
                max_size=40), st.booleans())
def test_any_values_cast_as_numpy_casts_them(values, in_place):
    x = np.array(values, np.float32).reshape(1, -1)
    want, _ = _expected(x)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        out = to_half(x.copy(), in_place=in_place)
    np.testing.assert_array_equal(out.view(np.uint16), want.view(np.uint16))
