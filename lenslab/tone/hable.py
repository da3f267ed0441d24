"""Hable's filmic curve (Uncharted 2): a toe, a linear section and a shoulder, white at W.

f(x) = (x (A x + C B) + D E) / (x (A x + B) + D F) - E / F, output min(f(bias x) / f(W), 1).
John Hable, "Filmic Tonemapping Operators" (blog, 2010): A=0.15 B=0.50 C=0.10 D=0.20 E=0.02 F=0.30,
exposure bias 2.0, W = 11.2 (the seed's defaults); his GDC 2010 talk "Uncharted 2: HDR Lighting" uses
A=0.22 B=0.30 E=0.01 (``preset="gdc"``).

>>> round(float(hable([1.0])[0]), 5)          # f(2.0) / f(11.2) with the blog constants
0.49292
>>> float(hable([5.6])[0])                    # 5.6 x bias 2.0 = W: white
1.0
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from lenslab.errors import ToneError
from lenslab.params import Param
from lenslab.tone.kernels import rational_kernel
from lenslab.tone.mapping import values
from lenslab.tone.registry import register

HABLE_PRESETS = {
    # Hable's blog post "Filmic Tonemapping Operators" (2010): the seed's constants
    "blog": dict(A=0.15, B=0.50, C=0.10, D=0.20, E=0.02, F=0.30),
    # Hable's GDC 2010 slides "Uncharted 2: HDR Lighting"
    "gdc": dict(A=0.22, B=0.30, C=0.10, D=0.20, E=0.01, F=0.30),
}


def _hable_check(p: dict) -> dict:
    """Fill the constants not given from the preset; refuse a set that is not monotonic."""
    preset = HABLE_PRESETS[p["preset"]]
    p = {k: (preset[k] if k in preset and v is None else v) for k, v in p.items()}
    A, B, C, D, E, F = (float(p[k]) for k in "ABCDEF")
    # f(x) - f(0) = x (A(F-E) x + B(CF-E)) / (F (A x^2 + B x + DF)); its slope has the numerator
    # AB(1-C) x^2 + 2AD(F-E) x + BD(CF-E), non-negative for every x >= 0 iff C <= 1 and E <= CF.
    if E > C * F + 1e-12:
        raise ToneError(f"curve 'hable': E={E:g} must not exceed C*F={C * F:g}, or the curve dips below 0 "
                        "and is not monotonic; lower E or raise C or F")
    if A * (F - E) <= 0 and B * (C * F - E) <= 0:
        raise ToneError("curve 'hable': the constants make the curve flat (A(F-E) and B(CF-E) both 0); "
                        "keep E below F")
    return p


def _hable_coefficients(p, scale=1.0):
    """(a1, a0, b1, b0, cap) of the rational kernel equal to hable at input ``x * scale``."""
    A, B, C, D, E, F = (float(p[k]) for k in "ABCDEF")
    P, Q, R = A * (F - E) / F, B * (C * F - E) / F, D * F  # f(v) - f(0) = v (P v + Q) / (A v^2 + B v + R)
    white = p["white"]
    g_white = white * (P * white + Q) / (white * (A * white + B) + R)
    k = p["exposure_bias"] * scale
    return (P * k * k / (R * g_white), Q * k / (R * g_white), A * k * k / R, B * k / R, white / k)


def _build_hable(p, scale):
    return rational_kernel(*_hable_coefficients(p, scale))


_HABLE_P = (
    Param("preset", "blog", "constant set: blog (A=0.15 B=0.50 E=0.02, his blog post's) or gdc "
          "(A=0.22 B=0.30 E=0.01)", choices=("blog", "gdc")),
    Param("exposure_bias", 2.0, "input multiplier before the curve", 0.0, 1e3, lo_open=True),
    Param("white", 11.2, "linear white W: f(bias x) / f(W), so x = W / bias reaches 1", 0.0, 1e6, lo_open=True),
    Param("A", None, "shoulder strength (default from preset)", 0.0, 10.0, lo_open=True),
    Param("B", None, "linear strength (default from preset)", 0.0, 10.0, lo_open=True),
    Param("C", None, "linear angle (default from preset)", 0.0, 1.0),
    Param("D", None, "toe strength (default from preset)", 0.0, 10.0, lo_open=True),
    Param("E", None, "toe numerator (default from preset)", 0.0, 10.0),
    Param("F", None, "toe denominator (default from preset)", 0.0, 10.0, lo_open=True),
)


@register("hable", "scalar", _HABLE_P, build=_build_hable, check=_hable_check)
def hable(x: ArrayLike, **params: float) -> np.ndarray:
    """Hable / Uncharted 2 filmic: y = min(f(bias x) / f(W), 1), f(x) = (x(Ax+CB)+DE) / (x(Ax+B)+DF) - E/F.

    Defaults: bias 2.0, W = 11.2, A=0.15 B=0.50 C=0.10 D=0.20 E=0.02 F=0.30 (John
    Hable, "Filmic Tonemapping Operators", 2010); ``preset="gdc"`` takes the set of his GDC 2010
    talk "Uncharted 2: HDR Lighting" (A=0.22 B=0.30 E=0.01). Every constant is a parameter.
    Evaluated as f(x) - f(0) = x (A(F-E) x + B(CF-E)) / (F (A x^2 + B x + DF)), equal in exact
    arithmetic and exactly 0 at 0 in floating point.

    Parameters
    ----------
    x : array_like
        Scene-linear values (any shape).
    **params
        ``preset`` ("blog" or "gdc") and any of the constants ``A``... ``F``, ``W`` and ``bias``
        (``lenslab curves --list`` shows their names and ranges).

    Returns
    -------
    numpy.ndarray
        float32 display-linear values in [0, 1], the shape of ``x``.

    Raises
    ------
    lenslab.errors.ToneError
        An unknown parameter, one out of range, or a set whose curve is not monotonic.

    Examples
    --------
    Black stays exactly black, and ``W / bias`` = 5.6 is white:

    >>> from lenslab.tone import hable
    >>> hable([0.0, 5.6, 100.0]).tolist()
    [0.0, 1.0, 1.0]
    """
    return values("hable", x, params)
