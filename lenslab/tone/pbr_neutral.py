"""Khronos PBR Neutral: colours pass unchanged (after a small toe) up to 0.76, then a shoulder.

Khronos Group, "PBR Neutral" tone mapper (2024), reference GLSL: offset = x - 6.25 x^2 below x = 0.08
(x the smallest channel), else 0.04; above a peak channel of 0.76, newPeak = 1 - 0.24^2 / (peak - 0.52)
scales the colour, then desaturates toward white by g = 1 - 1 / (0.15 (peak - newPeak) + 1).

>>> [round(float(v), 6) for v in pbr_neutral([[0.5, 0.5, 0.5]])[0]]          # 0.5 - 0.04
[0.46, 0.46, 0.46]
"""

from __future__ import annotations

import numpy as np

from lenslab.tone.kernels import BIG, F32, clip
from lenslab.tone.mapping import triples
from lenslab.tone.registry import register


def _build_pbr_neutral(p, scale):
    s = F32(scale)
    start, desat = 0.8 - 0.04, 0.15
    d = 1.0 - start

    def k(src, dst, scratch):  # planar (3, n) blocks; branch-free form of the reference shader
        v, t = scratch
        low, peak, ratio = v[0], v[1], v[2]
        new_peak, h = t[0], t[1]
        x = src  # repaired: finite and >= 0, which is all the steps below need
        if s != 1:
            np.multiply(src, s, out=dst)
            clip(dst, F32(0), BIG, out=dst)
            x = dst
        # toe offset: low - 6.25 low^2 below 0.08, else 0.04 (= the same expression at low = 0.08)
        np.fmin(np.fmin(x[0], x[1], out=low), x[2], out=low)
        clip(low, F32(0), F32(0.08), out=low)
        np.multiply(low, F32(-6.25), out=h)
        h += F32(1)
        low *= h
        np.subtract(x, low, out=dst)
        np.fmax(np.fmax(dst[0], dst[1], out=peak), dst[2], out=peak)
        # shoulder on the peak: below `start` the factors below are exactly 1 and 0
        clip(peak, F32(start), BIG, out=peak)
        np.add(peak, F32(d - start), out=new_peak)
        np.divide(F32(-d * d), new_peak, out=new_peak)
        new_peak += F32(1)
        np.divide(new_peak, peak, out=ratio)
        np.subtract(peak, new_peak, out=h)       # h = 1 / (desat (peak - newPeak) + 1) = 1 - g
        h *= F32(desat)
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
    """PBR Neutral on grey, monotone step by step: z = max(6.25 min(x, 0.08)^2, x - 0.04) (the toe),
    y = min(z, 0.76) + s(max(z, 0.76)) - s(0.76), s(z) = 1 - 0.24^2 / (z - 0.52), s(0.76) = 0.76."""
    s = F32(scale)
    start = 0.8 - 0.04
    d = 1.0 - start
    at_start = F32(-d * d) / (F32(start) + F32(d - start))  # the same float32 steps as below

    def k(src, dst, scratch):
        a, u = scratch
        np.multiply(src, s, out=dst)
        clip(dst, F32(0), BIG, out=dst)
        clip(dst, F32(0), F32(0.08), out=a)
        a *= a
        a *= F32(6.25)
        dst -= F32(0.04)
        np.fmax(dst, a, out=dst)                 # z
        clip(dst, F32(start), BIG, out=a)
        a += F32(d - start)
        np.divide(F32(-d * d), a, out=a)
        a -= at_start                            # s(max(z, start)) - s(start), exactly 0 at start
        clip(dst, F32(0), F32(start), out=dst)
        dst += a
        clip(dst, F32(0), F32(1), out=dst)
    return k


@register("pbr-neutral", "rgb", build=_build_pbr_neutral, build_grey=_build_pbr_neutral_grey)
def pbr_neutral(rgb) -> np.ndarray:
    """Khronos PBR Neutral: linear (after a toe offset) up to 0.76, then a shoulder on the peak
    channel, newPeak = 1 - 0.24^2 / (peak - 0.52), with desaturation 0.15 toward white.

    Khronos Group, "PBR Neutral" tone mapper (2024), reference GLSL. Base colours below the shoulder
    come out as they went in (minus the small toe offset). Acts on RGB triples.
    """
    return triples("pbr-neutral", rgb, {})
