"""The separable samplers' weights (``src/native/separable.cpp``: one sine and cosine per axis for Lanczos-3) against
the kernels' definitions transcribed here in float64, and the samplers across a panorama's seam and poles.

Outside values: the Lanczos-3 window ``sinc(t) sinc(t / 3)`` on ``|t| < 3`` (``np.sinc``, the normalised sinc) and
Keys' cubic with ``a = -1/2`` (Catmull-Rom), each normalised by its sum over the taps, as the samplers normalise.

Bounds. Lanczos: ``np.sinc`` takes the sine of ``pi t`` rounded to float64, an argument error of up to half an ulp of
``3 pi`` (8.9e-16) for ``|t| < 3``, so the definition's own weights are good to about 1e-15 absolute; the kernel's
(sine and cosine of ``pi g / 3``, ``|g| <= 1/2``, by a Taylor polynomial within 1 ulp of NumPy's, rotated, times a
product of six squares, then normalised) to a few 1e-16. 4e-15 absolute allows both (measured: 5.6e-16 on these
positions, 6.7e-16 on 1e5 uniform ones). Catmull-Rom: the same polynomial in another order and the normalisation, a
few float64 ulp (9.1e-16 measured, 2e-15 allowed). The normalised weights (each times the reciprocal of their sum)
sum to 1 within 2 ulp (measured; 8 allowed: the roundings of the sum, the reciprocal and six products). The kernel
against its NumPy reference (the same steps and polynomial): equal, 1e-15 allowed.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from lenslab import cxx_kernels
from lenslab.warp.filters import sample
from lenslab.warp.kernels import filter_reference as fref
from lenslab.warp.seam import Border
from tests.warp.test_native_map_kernels import keys, lanczos3  # the definitions, transcribed in float64

W, H = 8192, 4096  # an 8K panorama's columns and rows: positions of its seam and poles


def defined(kern, rad, x):
    """(n, 2 rad) weights of taps floor(x) - rad + 1 .. floor(x) + rad from the definition, normalised."""
    taps = np.floor(x)[:, None] + np.arange(-rad + 1, rad + 1)[None, :]
    w = kern(x[:, None] - taps)
    return w / w.sum(axis=1, keepdims=True)


def kernel(kind, x):
    w = np.zeros((len(x), 2 * kind))
    cxx_kernels.axis_weights(kind, np.ascontiguousarray(x, np.float64), w)
    return w


def f32(v):
    return float(np.float32(v))


EDGES = np.array([
    0.0, 1.0, 2.0, 5.0, 4095.0, W - 1.0, -1.0, -3.0,  # whole numbers: the removable singularity
    1e-300, 1.4e-45, 2.0 ** -20, 1.0 - 2.0 ** -20, 0.5, 0.5 - 2.0 ** -30, 0.5 + 2.0 ** -30, 2.5, -0.5, -0.25,
    f32(W - 1.0 + 0.999999), W - 0.5, W - 0.5 + 2.0 ** -12, -0.5 + 2.0 ** -13,  # the seam's positions (x)
    H - 0.5, H - 0.5 - 2.0 ** -12, f32(1e-7), -0.5 - 2.0 ** -13,  # the poles' (y: half a pixel beyond the rows)
    f32(W - 1.0 - 1e-4), f32(4095.0 + 1e-4), 2.0 ** 20 + 0.75, 2.0 ** 23 + 0.5,
])


@pytest.mark.parametrize("kind, kern, tol", [(3, lanczos3, 4e-15), (2, keys, 2e-15)], ids=["lanczos", "bicubic"])
def test_weights_are_the_kernels_definitions(kind, kern, tol):
    x = np.concatenate([EDGES, np.random.default_rng(3).uniform(-10, W + 10, 4000).astype(np.float32)])
    got = kernel(kind, x)
    np.testing.assert_allclose(got, defined(kern, kind, x), rtol=0, atol=tol)
    np.testing.assert_allclose(got.sum(axis=1), 1.0, rtol=0, atol=8 * np.finfo(np.float64).eps)  # normalised


def test_lanczos_at_whole_numbers_is_the_tap_itself():
    """At a pixel centre the window is 1 at its own tap and 0 at every other (sin(pi t) = 0 there): no 0/0."""
    x = np.array([0.0, 1.0, 7.0, -2.0, 4095.0, W - 1.0, 2.0 ** 23])
    want = np.zeros((len(x), 6))
    want[:, 2] = 1.0
    np.testing.assert_array_equal(np.abs(kernel(3, x)), want)


@settings(max_examples=300, deadline=None)
@given(st.floats(-2.0 ** 24, 2.0 ** 24, allow_nan=False, width=32))
def test_lanczos_weights_of_any_float32_position(x):
    got = kernel(3, np.array([x]))
    np.testing.assert_allclose(got, defined(lanczos3, 3, np.array([x])), rtol=0, atol=4e-15)


def test_lanczos_weights_match_the_reference():
    x = np.concatenate([EDGES, np.random.default_rng(4).uniform(-10, W + 10, 4000)])
    want = np.stack(fref.axis_weights(3, x), axis=1)
    np.testing.assert_allclose(kernel(3, x), want, rtol=0, atol=1e-15)


@pytest.mark.parametrize("name, kern, rad", [("lanczos", lanczos3, 3), ("bicubic", keys, 2)])
def test_taps_across_the_seam_and_over_the_poles(name, kern, rad):
    """A panorama (wrapped at the seam, folded over the poles onto the opposite meridian) read near both: the
    sample is the definition's weighted sum of the taps folded as an equirect panorama folds them."""
    w, h = 64, 32
    rng = np.random.default_rng(9)
    src = rng.uniform(0.0, 1.0, (h, w, 1)).astype(np.float32)
    x = np.array([-0.5, -0.2, 0.3, w - 0.5, w - 1.3, w - 0.7, 17.25, 40.5, 0.0, w - 1.0], np.float32)
    y = np.array([-0.5, -0.3, 0.2, h - 0.5, h - 0.8, 1.7, -0.45, h - 0.55, 0.0, h - 1.0], np.float32)
    out, alpha = np.zeros((1, len(x), 1), np.float32), np.zeros((1, len(x)), np.float32)
    sample(src, x[None, :, None], y[None, :, None], np.ones((1, len(x), 1), bool), Border(True, True, True), name,
           out, alpha)
    for q in range(len(x)):
        xq, yq = np.float64(x[q]), np.float64(y[q])
        i = np.floor(xq) + np.arange(-rad + 1, rad + 1)
        j = np.floor(yq) + np.arange(-rad + 1, rad + 1)
        wx, wy = defined(kern, rad, np.array([xq]))[0], defined(kern, rad, np.array([yq]))[0]
        want = 0.0
        for tj in range(2 * rad):
            for ti in range(2 * rad):
                jj, ii = int(j[tj]), int(i[ti])
                if jj < 0:  # over the top pole: the mirrored row on the opposite meridian
                    jj, ii = -1 - jj, ii + w // 2
                if jj >= h:
                    jj, ii = 2 * h - 1 - jj, ii + w // 2
                want += wx[ti] * wy[tj] * float(src[jj, ii % w, 0])
        # float64 sums in another order, then the output's float32 rounding (values below 1.5)
        assert out[0, q, 0] == pytest.approx(want, rel=0, abs=2 * float(np.finfo(np.float32).eps))
