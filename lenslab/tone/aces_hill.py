"""Stephen Hill's ACES fit: the ACES RRT+ODT on colours, with its matrices.

y = clamp(M_out fit(M_in rgb), 0, 1), fit(v) = (v (v + 0.0245786) - 0.000090537) /
(v (0.983729 v + 0.4329510) + 0.238081). Stephen Hill, BakingLab ``ACES.hlsl`` (2016). M_in: sRGB ->
XYZ -> D65-to-D60 -> AP1 -> RRT saturation; M_out: ODT saturation -> XYZ -> D60-to-D65 -> sRGB. The
matrices are the identity on grey to 5 digits, so on grey values (and on luminance) the curve is the
fit alone.

>>> [round(float(v), 5) for v in aces_hill([[0.18, 0.18, 0.18]])[0]]     # fit(0.18) = 0.036734 / 0.347889
[0.10559, 0.10559, 0.10559]
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from lenslab.tone.kernels import BIG, F32, FMAX, TINY, clip
from lenslab.tone.mapping import triples
from lenslab.tone.registry import register

# Stephen Hill's fit (BakingLab, ACES.hlsl): sRGB -> XYZ -> D65->D60 -> AP1 -> RRT_SAT, and back
ACES_HILL_INPUT = np.array([[0.59719, 0.35458, 0.04823],
                            [0.07600, 0.90834, 0.01566],
                            [0.02840, 0.13383, 0.83777]])
ACES_HILL_OUTPUT = np.array([[1.60475, -0.53108, -0.07367],
                             [-0.10208, 1.10813, -0.00605],
                             [-0.00327, -0.07276, 1.07602]])


# RRTAndODTFit: fit(v) = (v (v + A) - B) / (v (C v + D) + E)
A, B, C, D, E = 0.0245786, 0.000090537, 0.983729, 0.4329510, 0.238081


def _build_aces_hill(p, scale):
    """On colours: the fit as published, between the two matrices (negative near black, before the
    output matrix mixes the channels)."""
    m_in = (ACES_HILL_INPUT * scale).astype(F32)
    m_out = ACES_HILL_OUTPUT.astype(F32)

    def k(src, dst, scratch):  # planar (3, n) blocks
        v, t = scratch
        np.matmul(m_in, src, out=v)
        clip(v, F32(0), BIG, out=v)
        np.multiply(v, F32(C), out=t)
        t += F32(D)
        t *= v
        t += F32(E)
        np.add(v, F32(A), out=dst)  # src is no longer needed: dst serves as scratch
        dst *= v
        dst -= F32(B)
        np.divide(dst, t, out=v)
        np.matmul(m_out, v, out=dst)
        clip(dst, F32(0), F32(1), out=dst)
    return k


def _build_aces_hill_grey(p, scale):
    """On grey (the matrices are the identity on grey to 5 digits): the same fit, clipped at 0, in a
    form whose every step is monotone: 1 / fit = C + m / a + n / (v a), a = v + A - B / v, m = D - C A,
    n = E + C B; where a <= 0 the fit is <= 0 and the result 0."""
    s = F32(scale)
    m, n = F32(D - C * A), F32(E + C * B)

    def k(src, dst, scratch):
        a, u = scratch
        np.multiply(src, s, out=dst)
        clip(dst, F32(0), BIG, out=dst)
        np.divide(F32(B), dst, out=a)
        np.subtract(dst, a, out=a)
        a += F32(A)
        clip(a, TINY, FMAX, out=a)           # a = v + A - B / v
        np.multiply(dst, a, out=u)           # u = v a = v (v + A) - B
        np.divide(n, u, out=u)
        np.divide(m, a, out=a)
        a += u
        a += F32(C)
        np.divide(F32(1), a, out=dst)
        clip(dst, F32(0), F32(1), out=dst)
    return k


@register("aces-hill", "rgb", build=_build_aces_hill, build_grey=_build_aces_hill_grey)
def aces_hill(rgb: ArrayLike) -> np.ndarray:
    """ACES RRT+ODT fit by Stephen Hill: y = clamp(M_out fit(M_in rgb), 0, 1),
    fit(v) = (v (v + 0.0245786) - 0.000090537) / (v (0.983729 v + 0.4329510) + 0.238081).

    Stephen Hill, BakingLab ``ACES.hlsl`` (2016). M_in: sRGB -> XYZ -> D65-to-D60 -> AP1 -> RRT
    saturation; M_out: ODT saturation -> XYZ -> D60-to-D65 -> sRGB (:data:`ACES_HILL_INPUT`,
    :data:`ACES_HILL_OUTPUT`). Acts on RGB triples; on grey it is the fit alone.

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
    White in, grey out: the fit at 1 is 1.0245 / 1.6547 = 0.6191:

    >>> from lenslab.tone import aces_hill
    >>> [round(v, 4) for v in aces_hill([1.0, 1.0, 1.0]).tolist()]
    [0.6191, 0.6191, 0.6191]
    """
    return triples("aces-hill", rgb, {})
