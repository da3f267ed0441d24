"""The luminance mode's two compiled passes over a block of interleaved float32 RGB pixels (taken once
numba is loaded: :func:`lenslab.tone.sweep.compiled_ready`; NumPy's ufuncs run the same steps otherwise).

1. :func:`weigh_clean`: ``L = w . rgb`` and, in the same pass, the largest bit pattern of the block: a
   block whose every value is finite and >= +0 (the rule of :func:`lenslab.tone.sweep.is_clean`) is done.
   Otherwise :func:`weigh_pixels` weighs it again with bad values repaired as they are read (NaN and
   negatives count as 0, +inf as 0 until the end; nothing is written back), the repairs counted.
2. (the curve's kernel maps ``L`` to ``Ld``: :mod:`lenslab.tone.kernels`)
3. :func:`scale_clean` (or :func:`scale_pixels`, which repairs as it reads): ``rgb * Ld / L``; where
   the brightest channel would then pass 1, the pixel is blended toward the grey ``(Ld, Ld, Ld)`` of the
   same luminance, ``grey + (scaled - grey) t`` with ``t = (1 - Ld) / (peak - Ld)`` clipped to [0, 1],
   so luminance and hue angle survive and only saturation gives way; a pixel with a +inf channel is
   white. ``t`` is 1 wherever the peak is within range, so every pixel takes the same steps (the blend
   with ``t = 1`` is the scaled pixel to a float32 rounding).

Every step is float32, in the order written here (the weights' sum ``(w0 r + w1 g) + w2 b``), so a
pixel's result depends neither on its block nor on the thread. The clean passes have no branch (only
selects) and read the pixels as one 1-D array with a constant stride of 3, so the compiler vectorises
them; NumPy's error model lets a float division by zero give inf instead of checking for it in the loop.
"""

from __future__ import annotations

import numba
import numpy as np

from lenslab.tone.kernels import TINY  # added to L before dividing: black (L = 0) gets ratio 0

F0 = np.float32(0.0)
F1 = np.float32(1.0)
INF = np.float32(np.inf)


@numba.njit(inline="always", cache=True)
def _clean(v):
    """(repaired value, kind): kind 0 clean, 1 NaN, 2 +inf, 3 negative (-inf included)."""
    if v >= F0 and v < INF:
        return v, 0
    if v != v:
        return F0, 1
    if v == INF:
        return F0, 2
    if v < F0:
        return F0, 3
    return v, 0  # -0.0 compares equal to 0 and passes the first test; unreachable


@numba.njit(cache=True, nogil=True, error_model="numpy")
def weigh_clean(flat, bits, w0, w1, w2, lum):
    """``lum[i] = (w0 r + w1 g) + w2 b`` of pixel ``i`` of ``flat`` (interleaved RGB float32, 1-D: a
    constant stride the compiler vectorises); returns the largest of the values' bit patterns (``bits``
    is ``flat`` viewed as uint32): below 0x7F800000 (+inf) every value is finite and >= +0, and ``lum``
    is final."""
    top = np.uint32(0)
    for i in range(lum.shape[0]):
        top = max(top, max(bits[3 * i], max(bits[3 * i + 1], bits[3 * i + 2])))
        lum[i] = (w0 * flat[3 * i] + w1 * flat[3 * i + 1]) + w2 * flat[3 * i + 2]
    return top


@numba.njit(cache=True, nogil=True, error_model="numpy")
def scale_clean(flat, lum, mapped, out):
    """:func:`scale_pixels` for interleaved RGB float32 (1-D ``flat`` and ``out``) of finite values >= +0,
    without a branch: ``t`` is 1 wherever the scaled peak is within range (then the blend is the scaled
    pixel, to a float32 rounding), so every pixel takes the same steps."""
    for i in range(lum.shape[0]):
        ld = mapped[i]
        k = ld / (lum[i] + TINY)
        r = flat[3 * i] * k
        g = flat[3 * i + 1] * k
        b = flat[3 * i + 2] * k
        peak = max(r, max(g, b))
        t = min(F1, max(F0, (F1 - ld) / max(peak - ld, TINY)))
        out[3 * i] = min(F1, max(F0, ld + (r - ld) * t))
        out[3 * i + 1] = min(F1, max(F0, ld + (g - ld) * t))
        out[3 * i + 2] = min(F1, max(F0, ld + (b - ld) * t))


@numba.njit(cache=True, nogil=True, error_model="numpy")
def weigh_pixels(px, w0, w1, w2, lum):
    """``lum[i] = (w0 r + w1 g) + w2 b`` of pixel ``px[i]`` (n, 3) float32, bad values read as 0;
    returns the counts (NaN, +inf, negative) and the lowest negative value (0.0 when none)."""
    nan = 0
    posinf = 0
    neg = 0
    lowest = 0.0
    for i in range(px.shape[0]):
        r = px[i, 0]
        g = px[i, 1]
        b = px[i, 2]
        if not (r >= F0 and r < INF and g >= F0 and g < INF and b >= F0 and b < INF):
            for c in range(3):
                v = px[i, c]
                _, kind = _clean(v)
                if kind == 1:
                    nan += 1
                elif kind == 2:
                    posinf += 1
                elif kind == 3:
                    neg += 1
                    lowest = min(lowest, np.float64(v))
            r = _clean(r)[0]
            g = _clean(g)[0]
            b = _clean(b)[0]
        lum[i] = (w0 * r + w1 * g) + w2 * b
    return nan, posinf, neg, lowest


@numba.njit(cache=True, nogil=True, error_model="numpy")
def scale_pixels(px, lum, mapped, out):
    """``out[i]`` = pixel ``px[i]`` scaled by ``mapped[i] / lum[i]``, blended toward grey where it
    would pass 1, white where a channel is +inf (see the module docstring). ``out`` may be ``px``."""
    for i in range(px.shape[0]):
        r = px[i, 0]
        g = px[i, 1]
        b = px[i, 2]
        white = False
        if not (r >= F0 and r < INF and g >= F0 and g < INF and b >= F0 and b < INF):
            white = r == INF or g == INF or b == INF
            r = _clean(r)[0]
            g = _clean(g)[0]
            b = _clean(b)[0]
        if white:
            out[i, 0] = F1
            out[i, 1] = F1
            out[i, 2] = F1
            continue
        ld = mapped[i]
        k = ld / (lum[i] + TINY)
        r *= k
        g *= k
        b *= k
        peak = max(r, max(g, b))
        t = min(F1, max(F0, (F1 - ld) / max(peak - ld, TINY)))
        r = min(F1, max(F0, ld + (r - ld) * t))
        g = min(F1, max(F0, ld + (g - ld) * t))
        b = min(F1, max(F0, ld + (b - ld) * t))
        out[i, 0] = r
        out[i, 1] = g
        out[i, 2] = b
