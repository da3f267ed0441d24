"""AgX (Troy Sobotka), in Benjamin Wrensch's minimal form: a log encoding and a sigmoid on colours.

Inset matrix, log2 encoding over [-12.47393, 4.026069] EV, the 6th-order polynomial fit of the AgX
sigmoid 15.5t^6 - 40.14t^5 + 31.96t^4 - 6.868t^3 + 0.4298t^2 + 0.1191t - 0.00232, outset matrix,
then display-linear by the 2.2 power. Benjamin Wrensch, "Minimal AgX Implementation" (2024),
default look. The matrices are the identity on grey to 4 digits.

>>> round(float(agx([[0.18, 0.18, 0.18]])[0, 1]), 4)     # t = 10 / 16.5, sigmoid 0.49673, ^2.2
0.2145
"""

from __future__ import annotations

import numpy as np

from lenslab.tone.kernels import F32, clip, power_offset
from lenslab.tone.mapping import triples
from lenslab.tone.registry import register

# Benjamin Wrensch, "Minimal AgX Implementation" (2024), after Troy Sobotka's AgX
AGX_INSET = np.array([[0.842479062253094, 0.0784335999999992, 0.0792237451477643],
                      [0.0423282422610123, 0.878468636469772, 0.0791661274605434],
                      [0.0423756549057051, 0.0784336, 0.879142973793104]])
AGX_OUTSET = np.array([[1.19687900512017, -0.0980208811401368, -0.0990297440797205],
                       [-0.0528968517574562, 1.15190312990417, -0.0989611768448433],
                       [-0.0529716355144438, -0.0980434501171241, 1.15107367264116]])
AGX_MIN_EV, AGX_MAX_EV = -12.47393, 4.026069
AGX_POLY = (15.5, -40.14, 31.96, -6.868, 0.4298, 0.1191, -0.00232)  # t^6 ... t^0


# the 2.2 power takes the log of max(y, this): 2.2 log2 stays above -126, where exp2 is on its fast
# path (log2(0) and denormal results of exp2 cost 10 to 100 times more); its value is subtracted
_AGX_POWER_FLOOR = 2.0 ** -56


def _build_agx(p, scale):
    span = AGX_MAX_EV - AGX_MIN_EV
    # the log2 encoding t = (log2 v - min) / span, clipped to [0, 1], as w = log2(v 2^-min) clipped to
    # [0, span] (the 2^-min folded into the inset matrix) and t = w / span folded into the
    # polynomial's coefficients, a_i / span^i: Horner's partial sums are those of t scaled by powers
    # of span, so rounding is the same
    m_in = (AGX_INSET * scale * 2.0 ** -AGX_MIN_EV).astype(F32)
    m_out = AGX_OUTSET.astype(F32)
    v_hi = F32(2.0 ** span)
    poly = [F32(a / span ** (len(AGX_POLY) - 1 - i)) for i, a in enumerate(AGX_POLY)]
    floor, offset = F32(_AGX_POWER_FLOOR), power_offset(_AGX_POWER_FLOOR, 2.2, F32)

    def k_(src, dst, scratch):  # planar (3, n) blocks
        v, t = scratch
        np.matmul(m_in, src, out=v)
        clip(v, F32(1), v_hi, out=v)
        np.log2(v, out=v)
        np.multiply(v, poly[0], out=t)             # Horner: the 6th-order fit of the AgX sigmoid
        for coef in poly[1:-1]:
            t += coef
            t *= v
        t += poly[-1]
        np.matmul(m_out, t, out=dst)
        # the sigmoid's output is display-encoded with a 2.2 power: y = v^2.2 = exp2(2.2 log2 v)
        clip(dst, floor, F32(1), out=dst)
        np.log2(dst, out=dst)
        dst *= F32(2.2)
        np.exp2(dst, out=dst)
        dst -= offset                              # exactly 0 where the sigmoid is at or below 0
    return k_



def _build_agx_grey(p, scale):
    """AgX on grey: the sigmoid of the log2 encoding and the 2.2 power, without the inset and outset
    matrices (the identity on grey to 4 digits), in float64 so that rounding cannot reverse the order
    of two neighbouring inputs once the result is rounded to float32."""
    lo, span = AGX_MIN_EV, AGX_MAX_EV - AGX_MIN_EV
    offset = power_offset(_AGX_POWER_FLOOR, 2.2, np.float64)

    def k(src, dst, scratch):
        v = src.astype(np.float64) * scale
        clip(v, 1e-10, 1e15, out=v)
        np.log2(v, out=v)
        v -= lo
        v /= span
        clip(v, 0.0, 1.0, out=v)
        t = np.full_like(v, AGX_POLY[0])
        for coef in AGX_POLY[1:]:
            t *= v
            t += coef
        clip(t, _AGX_POWER_FLOOR, 1.0, out=t)
        np.log2(t, out=t)
        t *= 2.2
        np.exp2(t, out=t)
        t -= offset                          # exactly 0 where the sigmoid is at or below 0
        dst[...] = t
    return k



@register("agx", "rgb", build=_build_agx, build_grey=_build_agx_grey)
def agx(rgb) -> np.ndarray:
    """AgX: inset matrix, log2 encoding over [-12.47393, 4.026069] EV, the 6th-order sigmoid fit
    15.5t^6 - 40.14t^5 + 31.96t^4 - 6.868t^3 + 0.4298t^2 + 0.1191t - 0.00232, outset matrix, then
    display-linear by the 2.2 power.

    Troy Sobotka's AgX as in Benjamin Wrensch, "Minimal AgX Implementation" (2024), default look.
    Acts on RGB triples.
    """
    return triples("agx", rgb, {})
