"""``clamp`` and ``gamma``: the curves that only clip, as renderers without tone mapping do.

``clamp`` is y = min(x, 1). ``gamma`` writes the code value v = min(x, 1)^(1/gamma), a plain display
gamma in place of the sRGB curve; it is returned display-linear as y = sRGB_EOTF(v) (the sRGB
transfer function of :mod:`lenslab.srgb`), so that the sRGB encoding done when writing yields v, as
renderers that write ``pow(c, 1/2.2)`` do.

>>> float(clamp([0.5, 3.0])[1])
1.0
>>> from lenslab import srgb
>>> v = float(srgb.eotf_inverse(gamma([0.18], gamma=2.2)[0]))   # the code value written
>>> round(v, 5), round(0.18 ** (1 / 2.2), 5)
(0.45866, 0.45866)
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from lenslab import srgb
from lenslab.params import Param
from lenslab.tone.kernels import F32, clip
from lenslab.tone.mapping import values
from lenslab.tone.registry import register


def _build_clamp(p, scale):
    s = F32(scale)

    def k(src, dst, scratch):
        if s != 1:
            np.multiply(src, s, out=dst)
            src = dst
        clip(src, F32(0), F32(1), out=dst)
    return k


# smallest input the gamma kernel takes the log of: float32 log2 and exp2 run at full SIMD speed only
# away from 0 (log2(0) = -inf) and from denormal results (exp2 below -126), which cost 10 to 100 times more
_LOG2_FLOOR = -126.0


def _gamma_steps(values: np.ndarray, scale, inv: np.float32, floor: np.float32) -> np.ndarray:
    """v = min(x, 1)^(1/gamma) as the kernel computes it: exp2(log2(clip(s x, floor, 1)) / gamma)."""
    v = np.multiply(values, F32(scale), dtype=F32) if scale != 1 else values.astype(F32, copy=True)
    clip(v, floor, F32(1), out=v)
    np.log2(v, out=v)
    v *= inv
    np.exp2(v, out=v)
    return v


def _srgb_power_steps(v: np.ndarray, out: np.ndarray, gain) -> np.ndarray:
    """The power segment of the sRGB EOTF on max(v, knee), as the kernel computes it (in float32:
    gain exp2(2.4 log2(u + 0.055)), gain = 1.055^-2.4 to an ulp; every step monotone)."""
    clip(v, F32(srgb.KNEE), F32(1), out=out)
    out += F32(srgb.OFFSET)
    np.log2(out, out=out)
    out *= F32(srgb.POWER)
    np.exp2(out, out=out)
    out *= gain
    return out


def _build_gamma(p, scale):
    """y = sRGB_EOTF(v), v = min(x, 1)^(1/gamma), in closed form with float32 log2/exp2 (no table).

    Written as y = (clip(v, v0, knee) - v0) / 12.92' + (P(max(v, knee)) - P(knee)), P the power
    segment, v0 the value of v at the smallest input taken (see ``floor``) and 12.92' the slope that
    maps [v0, knee] onto [0, knee / 12.92] (v0 = 2^(-149/gamma) is below 1e-11 up to gamma 4, where
    the slope is 1/12.92 to float32). A sum of two monotone terms, each exactly 0 at x = 0 (the
    constants come from the same float32 steps), equal to the EOTF to float32 rounding: the segments
    meet at the knee to 3e-7 relative, as the standard's constants do."""
    g = float(p["gamma"])
    inv = F32(1.0 / g)
    # the smallest input whose log is taken: exp2's argument log2(x) / gamma stays >= -126 (normal
    # results, the fast path); inputs below it are black (their true value is below 3e-6 even at gamma 10)
    floor = F32(max(2.0 ** -149, 2.0 ** (_LOG2_FLOOR * g)))
    s = F32(scale)
    v0 = F32(_gamma_steps(np.zeros(16, F32), 1.0, inv, floor)[0])      # v at x = 0
    knee_lin = F32(srgb.KNEE) - v0
    slope = F32(srgb.KNEE / srgb.SLOPE / float(knee_lin))
    # 1.055^-2.4 rounded to float32, nudged by an ulp or two so that x >= 1 gives exactly 1
    gain = F32((1.0 + srgb.OFFSET) ** -srgb.POWER)
    for _ in range(8):
        p_knee = F32(_srgb_power_steps(np.zeros(16, F32), np.empty(16, F32), gain)[0])
        p_one = F32(_srgb_power_steps(np.ones(16, F32), np.empty(16, F32), gain)[0])
        top = F32(knee_lin * slope) + F32(p_one - p_knee)
        if top == 1:
            break
        gain = np.nextafter(gain, F32(np.inf if top < 1 else 0))
    clip_top = bool(top > 1)  # the value at v = 1 is the largest: clip only if still past 1

    def k(src, dst, scratch):
        a, _ = scratch
        if s != 1:
            np.multiply(src, s, out=dst)
            src = dst
        clip(src, floor, F32(1), out=dst)
        np.log2(dst, out=dst)                  # v = exp2(log2(x) / gamma)
        dst *= inv
        np.exp2(dst, out=dst)
        _srgb_power_steps(dst, a, gain)        # the power segment past the knee ...
        a -= p_knee
        dst -= v0                              # ... plus the linear one below it
        clip(dst, F32(0), knee_lin, out=dst)
        dst *= slope
        dst += a
        if clip_top:
            clip(dst, F32(0), F32(1), out=dst)
    return k


@register("clamp", "scalar", build=_build_clamp)
def clamp(x: ArrayLike) -> np.ndarray:
    """Clip to white: y = min(x, 1). What a plain conversion to 8 bits does: every value above 1 is lost.

    Parameters
    ----------
    x : array_like
        Scene-linear values (any shape).

    Returns
    -------
    numpy.ndarray
        float32 display-linear values in [0, 1], the shape of ``x``.

    Examples
    --------
    >>> from lenslab.tone import clamp
    >>> clamp([0.5, 2.0]).tolist()
    [0.5, 1.0]
    """
    return values("clamp", x, {})


@register("gamma", "scalar", (Param("gamma", 2.2, "display gamma", 0.1, 10.0),), build=_build_gamma)
def gamma(x: ArrayLike, gamma: float = 2.2) -> np.ndarray:
    """Plain display gamma: code value v = min(x, 1)^(1/gamma) instead of the sRGB curve.

    Returned display-linear as y = sRGB_EOTF(v) (IEC 61966-2-1 as colour-science defines it,
    evaluated in closed form to float32 rounding), so that the sRGB encoding done when writing yields
    v, as renderers that write ``pow(c, 1/2.2)`` do. Exactly 0 at 0 and exactly 1 from x = 1 up.

    Parameters
    ----------
    x : array_like
        Scene-linear values (any shape).
    gamma : float
        The display gamma, in [0.1, 10].

    Returns
    -------
    numpy.ndarray
        float32 display-linear values in [0, 1], the shape of ``x``.

    Examples
    --------
    With ``gamma=2.2`` (the sRGB curve's own exponent is 2.4 past its linear toe) the code value of
    0.5 is ``0.5 ** (1 / 2.2)`` = 0.72974, which the sRGB decoding takes back to 0.49151:

    >>> from lenslab.tone import gamma
    >>> [round(v, 5) for v in gamma([0.0, 0.5, 2.0]).tolist()]
    [0.0, 0.49151, 1.0]
    """
    return values("gamma", x, {"gamma": gamma})
