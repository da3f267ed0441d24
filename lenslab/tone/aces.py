"""Narkowicz's ACES filmic fit: one rational curve per channel.

y = clamp(x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14), 0, 1). Krzysztof Narkowicz, "ACES Filmic
Tone Mapping Curve" (blog, 2016): a fit of the ACES RRT+ODT luminance response (for the fit on
colours, with the ACES matrices, see :mod:`lenslab.tone.aces_hill`).

>>> round(float(aces([1.0])[0]), 6)            # 2.54 / 3.16
0.803797
>>> float(aces([100.0])[0])
1.0
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from lenslab.tone.kernels import rational_kernel
from lenslab.tone.mapping import values
from lenslab.tone.registry import register

_ACES = dict(a=2.51, b=0.03, c=2.43, d=0.59, e=0.14)


def _build_aces(p, scale):
    a, b, c, d, e = (_ACES[k] for k in "abcde")
    # the fit passes 1 where (a-c) x^2 + (b-d) x - e = 0 (x ~ 7.24); capping the input past that point
    # changes nothing after the clamp and keeps x^2 finite
    x1 = ((d - b) + math.sqrt((b - d) ** 2 + 4 * (a - c) * e)) / (2 * (a - c))
    s = scale
    return rational_kernel(a * s * s / e, b * s / e, c * s * s / e, d * s / e, 2 * x1 / s)


@register("aces", "scalar", build=_build_aces)
def aces(x: ArrayLike) -> np.ndarray:
    """ACES filmic fit (Narkowicz): y = clamp(x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14), 0, 1).

    Krzysztof Narkowicz, "ACES Filmic Tone Mapping Curve", 2016: a fit of the ACES RRT+ODT luminance
    response, per channel.

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
    >>> from lenslab.tone import aces
    >>> [round(v, 6) for v in aces([0.0, 1.0, 100.0]).tolist()]  # 2.54 / 3.16 at 1
    [0.0, 0.803797, 1.0]
    """
    return values("aces", x, {})
