"""Reinhard's photographic operator: ``reinhard``, ``reinhard-extended`` and ``reinhard2002``.

Reinhard, Stark, Shirley, Ferwerda, "Photographic Tone Reproduction for Digital Images", SIGGRAPH
2002: eq. 3 is y = L / (1 + L); eq. 4 adds a white point, y = L (1 + L / Lw^2) / (1 + L), which
reaches 1 at L = Lw; eqs. 1-2 scale the image so that its log-average luminance
Lavg = exp(mean(log(delta + Lw))) lands on the key a: L = (a / Lavg) Lw.

>>> [round(float(v), 6) for v in reinhard([0.0, 1.0, 3.0])]
[0.0, 0.5, 0.75]
>>> round(float(reinhard_extended([2.0], white=4.0)[0]), 6)      # 2 (1 + 2/16) / 3
0.75
>>> round(float(reinhard2002(np.full(4, 2.0, np.float32))[0]), 4)  # a uniform image lands on the key: a / (1 + a)
0.1525
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from lenslab.params import Param
from lenslab.tone.exposure import MIDDLE_GREY, log_average, luminance_sample
from lenslab.tone.kernels import F32, rational_kernel
from lenslab.tone.mapping import as_float32, values, warn_repairs
from lenslab.tone.registry import get_curve, register
from lenslab.tone.sweep import Counts, sweep_values


def _build_reinhard(p, scale):
    c = F32(1.0 / scale)  # s x / (1 + s x) == 1 / (1 + (1/s) / x): monotone steps only, 0 at 0

    def k(src, dst, scratch):
        np.divide(c, src, out=dst)
        dst += F32(1)
        np.divide(F32(1), dst, out=dst)
    return k


def _build_reinhard_ext(p, scale):
    # x (1 + x / Lw^2) / (1 + x) with x -> s x: the rational form with numerator x^2/Lw^2 + x;
    # capped at Lw, where it is exactly 1
    white, s = p["white"], scale
    return rational_kernel(s * s / white**2, s, 0.0, s, white / s)


@register("reinhard", "scalar", build=_build_reinhard)
def reinhard(x: ArrayLike) -> np.ndarray:
    """Reinhard: y = x / (1 + x). Never reaches 1.

    Reinhard et al., "Photographic Tone Reproduction for Digital Images", SIGGRAPH 2002, eq. 3.

    Parameters
    ----------
    x : array_like
        Scene-linear values (any shape).

    Returns
    -------
    numpy.ndarray
        float32 display-linear values in [0, 1), the shape of ``x``.

    Examples
    --------
    >>> from lenslab.tone import reinhard
    >>> reinhard([0.0, 1.0, 3.0]).tolist()
    [0.0, 0.5, 0.75]
    """
    return values("reinhard", x, {})


@register("reinhard-extended", "scalar",
          (Param("white", 4.0, "input that maps to white (Lw)", 0.0, 1e6, lo_open=True),),
          build=_build_reinhard_ext)
def reinhard_extended(x: ArrayLike, white: float = 4.0) -> np.ndarray:
    """Reinhard with a white point: y = min(x (1 + x / Lw^2) / (1 + x), 1); y(Lw) = 1.

    Reinhard et al. 2002, eq. 4 (Lw = ``white``).

    Parameters
    ----------
    x : array_like
        Scene-linear values (any shape).
    white : float
        The input that maps to white (Lw), > 0.

    Returns
    -------
    numpy.ndarray
        float32 display-linear values in [0, 1], the shape of ``x``.

    Raises
    ------
    lenslab.errors.ToneError
        ``white`` out of its range.

    Examples
    --------
    >>> from lenslab.tone import reinhard_extended
    >>> reinhard_extended([1.0, 4.0, 8.0], white=4.0).tolist()  # 1 (1 + 1/16) / 2 = 0.53125
    [0.53125, 1.0, 1.0]
    """
    return values("reinhard-extended", x, {"white": white})


def _build_reinhard2002(p, scale):
    if math.isinf(p["white"]):
        return _build_reinhard(p, scale)
    return _build_reinhard_ext({"white": p["white"]}, scale)


@register("reinhard2002", "image",
          (Param("key", MIDDLE_GREY, "key value a: the log-average maps here", 0.0, 1.0, lo_open=True),
           Param("white", math.inf, "burn-out white Lwhite in scaled units (inf: none)", 0.0, math.inf,
                 lo_open=True),
           Param("delta", 1e-4, "delta in the log-average (keeps black pixels finite)", 0.0, 1.0,
                 lo_open=True)),
          build=_build_reinhard2002)
def reinhard2002(x: ArrayLike, key: float = MIDDLE_GREY, white: float = math.inf, delta: float = 1e-4,
                 log_avg: float | None = None) -> np.ndarray:
    """Reinhard et al. 2002 global operator: L = (a / Lavg) x, Lavg = exp(mean(log(delta + Lw))),
    then y = L (1 + L / Lwhite^2) / (1 + L) (y = L / (1 + L) with white = inf).

    Reinhard, Stark, Shirley, Ferwerda, "Photographic Tone Reproduction for Digital Images",
    SIGGRAPH 2002, eqs. 1-4. The log-average is taken over ``x`` itself (or given as ``log_avg``);
    in :func:`tonemap` it is the image's luminance, so any exposure cancels out.

    Parameters
    ----------
    x : array_like
        Scene-linear values (any shape).
    key : float
        The key value ``a`` in (0, 1]: the log-average maps here before the curve.
    white : float
        Burn-out white ``Lwhite`` in scaled units (inf: none, the plain ``L / (1 + L)``).
    delta : float
        The small ``delta`` of the log-average, keeping black pixels finite.
    log_avg : float, optional
        The log-average to use instead of the one of ``x``.

    Returns
    -------
    numpy.ndarray
        float32 display-linear values in [0, 1], the shape of ``x``.

    Raises
    ------
    lenslab.errors.ToneError
        A parameter out of its range.

    Examples
    --------
    The log-average maps to ``a``, then the curve: twice the log-average at ``a = 0.5`` is ``L = 1``,
    which shows as 0.5; a flat image lands at ``a / (1 + a)`` whatever its exposure:

    >>> from lenslab.tone import reinhard2002
    >>> reinhard2002([1.0, 2.0, 4.0], key=0.5, log_avg=2.0).tolist()
    [0.20000000298023224, 0.3333333432674408, 0.5]
    >>> round(float(reinhard2002([7.0] * 3, key=0.5)[0]), 4), round(float(reinhard2002([0.5] * 3, key=0.5)[0]), 4)
    (0.3333, 0.3333)
    """
    arr = as_float32(x)
    p = get_curve("reinhard2002").resolve({"key": key, "white": white, "delta": delta})
    if log_avg is None:
        log_avg = log_average(luminance_sample(arr.reshape(-1), None), delta=p["delta"])
    scale = p["key"] / max(float(log_avg), 1e-30)
    out = np.empty_like(arr)
    counts = Counts()
    with np.errstate(divide="ignore", over="ignore"):
        sweep_values(arr.reshape(-1), out.reshape(-1), _build_reinhard2002(p, scale), counts)
    warn_repairs(counts, arr.size, arr)
    return out
