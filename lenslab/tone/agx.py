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
from numpy.typing import ArrayLike

from lenslab.tone.kernels import F32, clip, native, pixel_kernel, power_offset
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
_SPAN = AGX_MAX_EV - AGX_MIN_EV


class _Steps:
    """The AgX curve after the inset matrix, written once for both kernels in the dtype they work in
    (float32 on colours; float64 on grey, so that rounding cannot reverse the order of two neighbouring
    inputs once the result is rounded to float32).

    The log2 encoding t = (log2 v - min) / span, clipped to [0, 1], is w = log2(v 2^-min) with v 2^-min
    clipped to [1, 2^span] (``gain`` folds 2^-min into what multiplies the input) and t = w / span
    folded into the polynomial's coefficients, a_i / span^i: Horner's partial sums are those in t
    scaled by powers of span, so the rounding is the same."""

    def __init__(self, dtype):
        self.dtype = dtype
        self.gain = 2.0 ** -AGX_MIN_EV
        self.top = dtype(2.0 ** _SPAN)
        self.poly = [dtype(a / _SPAN ** (len(AGX_POLY) - 1 - i)) for i, a in enumerate(AGX_POLY)]
        self.floor = dtype(_AGX_POWER_FLOOR)
        self.offset = power_offset(_AGX_POWER_FLOOR, 2.2, dtype)

    def sigmoid(self, v, t):
        """t = the sigmoid of the encoding of v (v already times ``gain``; v is overwritten)."""
        one = self.dtype(1)
        clip(v, one, self.top, out=v)
        np.log2(v, out=v)
        np.multiply(v, self.poly[0], out=t)        # Horner: the 6th-order fit of the AgX sigmoid
        for coef in self.poly[1:-1]:
            t += coef
            t *= v
        t += self.poly[-1]

    def display(self, y):
        """y = y^2.2 in place, as exp2(2.2 log2 y) above the floor; exactly 0 where y <= 0."""
        clip(y, self.floor, self.dtype(1), out=y)
        np.log2(y, out=y)
        y *= self.dtype(2.2)
        np.exp2(y, out=y)
        y -= self.offset


def _build_agx(p, scale):
    """The compiled pixel kernel (``src/native/tone_agx.cpp``): the same steps, with w, the polynomial
    and the outset matrix in float64 (``_Steps(np.float64)``'s constants) and the 2.2 power without a
    log or an exp; within 2e-7 of the float64 formula (the NumPy kernel: 1.1e-5). The NumPy kernel
    runs where the extension is not built."""
    compiled = native()
    if compiled is None:
        return _build_agx_numpy(p, scale)
    steps = _Steps(np.float64)
    m_in = np.ascontiguousarray(AGX_INSET * (scale * steps.gain))
    m_out = np.ascontiguousarray(AGX_OUTSET)
    poly, top = np.array(steps.poly), float(steps.top)

    @pixel_kernel
    def k(src, dst):
        return compiled.agx_pixels(src, dst, m_in, m_out, poly, top, _AGX_POWER_FLOOR, 2.2)
    return k


def _build_agx_numpy(p, scale):
    """The NumPy reference kernel, in float32 on planar blocks."""
    steps = _Steps(F32)
    m_in = (AGX_INSET * (scale * steps.gain)).astype(F32)
    m_out = AGX_OUTSET.astype(F32)

    def k_(src, dst, scratch):  # planar (3, n) blocks
        v, t = scratch
        np.matmul(m_in, src, out=v)
        steps.sigmoid(v, t)
        np.matmul(m_out, t, out=dst)
        steps.display(dst)
    return k_


def _build_agx_grey(p, scale):
    """AgX on grey: the same steps without the inset and outset matrices (the identity on grey to 4
    digits), in float64."""
    steps = _Steps(np.float64)
    gain = scale * steps.gain

    def k(src, dst, scratch):
        v = np.multiply(src, gain, dtype=np.float64)
        t = np.empty_like(v)
        steps.sigmoid(v, t)
        steps.display(t)
        dst[...] = t
    return k


@register("agx", "rgb", build=_build_agx, build_grey=_build_agx_grey)
def agx(rgb: ArrayLike) -> np.ndarray:
    """AgX: inset matrix, log2 encoding over [-12.47393, 4.026069] EV, the 6th-order sigmoid fit
    15.5t^6 - 40.14t^5 + 31.96t^4 - 6.868t^3 + 0.4298t^2 + 0.1191t - 0.00232, outset matrix, then
    display-linear by the 2.2 power.

    Troy Sobotka's AgX as in Benjamin Wrensch, "Minimal AgX Implementation" (2024), default look.
    Acts on RGB triples.

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
    Middle grey stays grey, a little brighter:

    >>> from lenslab.tone import agx
    >>> [round(v, 3) for v in agx([0.18, 0.18, 0.18]).tolist()]
    [0.214, 0.215, 0.215]
    """
    return triples("agx", rgb, {})
