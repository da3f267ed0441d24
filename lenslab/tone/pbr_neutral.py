"""Khronos PBR Neutral: colours pass unchanged (after a small toe) up to 0.76, then a shoulder.

Khronos Group, "PBR Neutral" tone mapper (2024), reference GLSL: offset = x - 6.25 x^2 below x = 0.08
(x the smallest channel), else 0.04; above a peak channel of 0.76, newPeak = 1 - 0.24^2 / (peak - 0.52)
scales the colour, then desaturates toward white by g = 1 - 1 / (0.15 (peak - newPeak) + 1).

>>> [round(float(v), 6) for v in pbr_neutral([[0.5, 0.5, 0.5]])[0]]          # 0.5 - 0.04
[0.46, 0.46, 0.46]
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from lenslab.tone.kernels import BIG, F32, clip, native, pixel_kernel
from lenslab.tone.mapping import triples
from lenslab.tone.registry import register


F90, KS, KD = 0.04, 0.8 - 0.04, 0.15  # the specification's names: Fresnel F90, compression start, desaturation
_D = 1.0 - KS


def _shoulder(peak, out):
    """out = newPeak = 1 - (1 - Ks)^2 / (peak + 1 - 2 Ks), with ``peak`` raised to Ks first (in place):
    the shoulder, shared by both kernels; exactly Ks at and below Ks."""
    clip(peak, F32(KS), BIG, out=peak)
    np.add(peak, F32(_D - KS), out=out)
    np.divide(F32(-_D * _D), out, out=out)
    out += F32(1)


def _build_pbr_neutral(p, scale):
    """The compiled pixel kernel (the NumPy kernel's float32 steps in its order: the same bits), or the
    NumPy kernel where the extension is not built."""
    compiled = native()
    if compiled is None:
        return _build_pbr_neutral_numpy(p, scale)
    constants = np.array([scale, BIG, 2 * F90, -1 / (4 * F90), KS, _D - KS, -_D * _D, KD], F32)

    @pixel_kernel
    def k(src, dst):
        return compiled.pbr_neutral_pixels(src, dst, constants)
    return k


def _build_pbr_neutral_numpy(p, scale):
    """The NumPy reference kernel, on planar blocks."""
    s = F32(scale)

    def k(src, dst, scratch):  # planar (3, n) blocks; branch-free form of the reference shader
        v, t = scratch
        low, peak, ratio = v[0], v[1], v[2]
        new_peak, h = t[0], t[1]
        x = src  # repaired: finite and >= 0, which is all the steps below need
        if s != 1:
            np.multiply(src, s, out=dst)
            clip(dst, F32(0), BIG, out=dst)
            x = dst
        # toe offset f: low - low^2 / (4 F90) below 2 F90, else F90 (= the same expression at 2 F90)
        np.fmin(np.fmin(x[0], x[1], out=low), x[2], out=low)
        clip(low, F32(0), F32(2 * F90), out=low)
        np.multiply(low, F32(-1 / (4 * F90)), out=h)
        h += F32(1)
        low *= h
        np.subtract(x, low, out=dst)
        np.fmax(np.fmax(dst[0], dst[1], out=peak), dst[2], out=peak)
        _shoulder(peak, new_peak)                # below Ks the factors below are exactly 1 and 0
        np.divide(new_peak, peak, out=ratio)
        np.subtract(peak, new_peak, out=h)       # h = 1 / (Kd (peak - newPeak) + 1) = 1 - g
        h *= F32(KD)
        h += F32(1)
        np.divide(F32(1), h, out=h)
        ratio *= h                               # out = c (ratio h) + newPeak (1 - h)
        np.subtract(F32(1), h, out=h)
        h *= new_peak
        dst *= ratio
        dst += h
        clip(dst, F32(0), F32(1), out=dst)
    return k


def _build_pbr_neutral_grey(p, scale):
    """PBR Neutral on grey, where the colour is its own peak and the result is newPeak: monotone step
    by step, z = max(min(x, 2 F90)^2 / (4 F90), x - F90) (x minus the toe offset), then
    y = min(z, Ks) + shoulder(max(z, Ks)) - shoulder(Ks), shoulder(Ks) = Ks."""
    s = F32(scale)
    at_start = np.full(1, KS, F32)
    _shoulder(at_start.copy(), at_start)         # shoulder(Ks) by the same float32 steps

    def k(src, dst, scratch):
        a, u = scratch
        np.multiply(src, s, out=dst)
        clip(dst, F32(0), BIG, out=dst)
        clip(dst, F32(0), F32(2 * F90), out=a)
        a *= a
        a *= F32(1 / (4 * F90))
        dst -= F32(F90)
        np.fmax(dst, a, out=dst)                 # z
        np.copyto(a, dst)
        _shoulder(a, u)
        u -= at_start[0]                         # shoulder(max(z, Ks)) - shoulder(Ks), exactly 0 at Ks
        clip(dst, F32(0), F32(KS), out=dst)
        dst += u
        clip(dst, F32(0), F32(1), out=dst)
    return k


@register("pbr-neutral", "rgb", build=_build_pbr_neutral, build_grey=_build_pbr_neutral_grey)
def pbr_neutral(rgb: ArrayLike) -> np.ndarray:
    """Khronos PBR Neutral: linear (after a toe offset) up to 0.76, then a shoulder on the peak
    channel, newPeak = 1 - 0.24^2 / (peak - 0.52), with desaturation 0.15 toward white.

    Khronos Group, "PBR Neutral" tone mapper (2024), reference GLSL. Base colours below the shoulder
    come out as they went in (minus the small toe offset). Acts on RGB triples.

    Parameters
    ----------
    rgb : array_like
        Scene-linear RGB, ``(..., 3)``.

    Returns
    -------
    numpy.ndarray
        float32 display-linear RGB in [0, 1], the shape of ``rgb``.

    Examples
    --------
    Below the shoulder only the toe offset 0.04 is taken off; black stays black:

    >>> from lenslab.tone import pbr_neutral
    >>> [[round(v, 6) for v in rgb] for rgb in pbr_neutral([[0.5, 0.5, 0.5], [0.0, 0.0, 0.0]]).tolist()]
    [[0.46, 0.46, 0.46], [0.0, 0.0, 0.0]]
    """
    return triples("pbr-neutral", rgb, {})
