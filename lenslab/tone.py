"""Tone curves: scene-linear HDR values -> display-linear values in [0, 1].

``tonemap(image, curve="hable", exposure=0.0, mode="per-channel", **params)`` is the one entry point the
rest of lenslab uses; it returns display-linear float32 (not yet sRGB-encoded: ``lenslab.io.write``
encodes). The order of work is fixed:

1. bad values are repaired and counted: NaN -> 0, +inf -> white, negatives (and -inf) -> 0; when there
   were any, a :class:`ToneWarning` carrying the counts is issued (never silently);
2. exposure in stops, ``x * 2**EV``; ``exposure="auto"`` picks EV so that the log-average luminance,
   with the darkest and brightest percent of the pixels left out, lands on middle grey (0.18);
3. the curve, either on each channel (``mode="per-channel"``) or on luminance (``mode="luminance"``:
   RGB is scaled by ``curve(L) / L``, which keeps the ratios between channels, i.e. the hue; a pixel
   whose brightest channel would then pass 1 is blended toward grey of the same luminance until it
   fits, so luminance and hue angle survive and only saturation gives way).

Every curve lives in :data:`CURVES` (name -> :class:`Curve`) with its declared parameters, ranges and
defaults; an unknown name or a parameter out of range raises :class:`lenslab.errors.ToneError` listing
what is valid. The closed-form curves are also module functions (``hable(x, **params)`` ...) that
take any float array and return float32 of the same shape.

Order: every curve except the local ones is monotone in float32 itself, not only on paper. The
rational curves are evaluated in a form whose every step is a rounded monotone operation (the plain
ratio of two increasing polynomials can step back by an ulp between neighbouring inputs); the RGB
curves (aces-hill, agx, pbr-neutral) use such a form on grey and on luminance.

Speed: the closed-form curves run over the image in cache-sized blocks with in-place float32
ufuncs, exposure folded into the curve's constants, so one sweep through memory does the repair,
the exposure and the curve. Powers are float32 log2/exp2 pairs whose arguments are kept away from
log2(0) and from denormal results of exp2 (NumPy's SIMD loops leave their fast path there and run
10 to 100 times slower: a black border would otherwise cost more than the rest of the image); the
offset this floor leaves is subtracted, so 0 still maps to exactly 0.
"""

from __future__ import annotations

import functools
import math
import warnings
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from lenslab.errors import ToneError

__all__ = [
    "CURVES", "Curve", "Param", "ToneWarning", "tonemap", "auto_exposure", "log_average",
    "luminance_weights", "curve_names", "get_curve", "describe_curves",
    "clamp", "gamma", "reinhard", "reinhard_extended", "reinhard2002", "hable", "aces", "aces_hill",
    "agx", "pbr_neutral", "drago", "mantiuk",
    "HABLE_PRESETS", "EXPOSURE_RANGE", "MIDDLE_GREY",
]

F32 = np.float32
MIDDLE_GREY = 0.18
#: exposure accepted, in stops (2**100 and 2**-100 are still ordinary float32 numbers)
EXPOSURE_RANGE = (-100.0, 100.0)
_BLOCK = 1 << 16  # values per block: the block and two scratch buffers stay inside a core's L2 cache
_TINY = F32(1e-37)  # smallest luminance divided by (below it a pixel is black to float32)
# the clip ufunc itself: np.clip's argument handling costs ~3 us a call, more than clipping a block
# in cache; where numpy does not expose it, np.clip does the same
_clip = getattr(getattr(getattr(np, "_core", None), "umath", None), "clip", None) or np.clip
_BIG = F32(1e15)  # inputs are capped here where a curve squares them (1e30 still fits in float32)
_FMAX = F32(np.finfo(np.float32).max)


class ToneWarning(UserWarning):
    """Bad input values were repaired while tone mapping. ``nan``, ``posinf`` and ``negative`` hold
    the counts (negative includes -inf); ``total`` is the number of values looked at."""

    def __init__(self, message: str, nan: int = 0, posinf: int = 0, negative: int = 0, total: int = 0):
        super().__init__(message)
        self.nan, self.posinf, self.negative, self.total = int(nan), int(posinf), int(negative), int(total)


# ---------------------------------------------------------------------------------------------
# Parameters and the registry


@dataclass(frozen=True)
class Param:
    """One declared curve parameter: a number in ``[low, high]`` (open ends where flagged), or one
    of ``choices``. ``default=None`` means "taken from another parameter" (see ``doc``)."""

    name: str
    default: float | str | None
    doc: str
    low: float = -math.inf
    high: float = math.inf
    low_open: bool = False
    high_open: bool = False
    choices: tuple[str, ...] | None = None

    def range_text(self) -> str:
        if self.choices:
            return "one of " + ", ".join(self.choices)
        lo = "(" if self.low_open else "["
        hi = ")" if self.high_open else "]"
        return f"{lo}{_num(self.low)}, {_num(self.high)}{hi}"

    def describe(self) -> str:
        default = "(preset)" if self.default is None else _num(self.default)
        return f"{self.name}={default}  {self.range_text()}  {self.doc}"

    def check(self, curve: str, value) -> float | str:
        if self.choices:
            text = str(value).strip().lower()
            if text not in self.choices:
                raise ToneError(f"curve {curve!r}: {self.name}={value!r} is not valid; use {self.range_text()}")
            return text
        try:
            number = float(value)
        except (TypeError, ValueError):
            raise ToneError(f"curve {curve!r}: {self.name}={value!r} is not a number; "
                            f"give a number in {self.range_text()}") from None
        too_low = number <= self.low if self.low_open else number < self.low
        too_high = number >= self.high if self.high_open else number > self.high
        if math.isnan(number) or too_low or too_high:
            raise ToneError(f"curve {curve!r}: {self.name}={_num(number)} is out of range; "
                            f"give a number in {self.range_text()} (default {_num(self.default)})")
        return number


def _num(v) -> str:
    if isinstance(v, str) or v is None:
        return str(v)
    if math.isinf(v):
        return "inf" if v > 0 else "-inf"
    return f"{v:g}"


@dataclass(frozen=True)
class Curve:
    """A registered tone curve.

    ``kind`` says how it acts: ``"scalar"`` (one pure function of each value), ``"rgb"`` (acts on RGB
    triples: colour matrices or a cross-channel rule; on luminance or grey data it acts on (L, L, L)),
    ``"image"`` (a scalar curve whose scale comes from the image's log-average) or ``"local"``
    (OpenCV operators whose result at a pixel depends on the whole image; they always work on
    luminance with their own saturation control, so ``mode`` does not apply).
    """

    name: str
    function: Callable
    params: tuple[Param, ...]
    kind: str
    summary: str
    build: Callable | None = field(default=None, repr=False)  # (resolved params, scale) -> kernel
    build_grey: Callable | None = field(default=None, repr=False)  # "rgb" curves: the kernel on grey values

    @property
    def doc(self) -> str:
        return (self.function.__doc__ or self.summary).strip()

    def resolve(self, params: dict | None = None) -> dict:
        """Validated parameters with defaults filled in; raises ToneError on unknown names or bad values."""
        params = dict(params or {})
        known = {p.name: p for p in self.params}
        unknown = [k for k in params if k not in known]
        if unknown:
            if known:
                valid = "; ".join(p.describe() for p in self.params)
                raise ToneError(f"curve {self.name!r} has no parameter {', '.join(map(repr, unknown))}; "
                                f"its parameters are: {valid}")
            raise ToneError(f"curve {self.name!r} takes no parameters (got {', '.join(map(repr, unknown))})")
        out = {}
        for p in self.params:
            out[p.name] = p.check(self.name, params[p.name]) if p.name in params and params[p.name] is not None \
                else p.default
        check = _CROSS_CHECKS.get(self.name)
        return check(out) if check else out


CURVES: dict[str, Curve] = {}
_CROSS_CHECKS: dict[str, Callable[[dict], dict]] = {}


def _register(name: str, kind: str, params: tuple[Param, ...] = (), build: Callable | None = None,
              build_grey: Callable | None = None):
    def deco(fn):
        first_paragraph = (fn.__doc__ or "").strip().split("\n\n")[0]
        summary = " ".join(line.strip() for line in first_paragraph.splitlines())
        CURVES[name] = Curve(name, fn, params, kind, summary, build, build_grey)
        return fn
    return deco


def curve_names() -> list[str]:
    """Every registered curve name, in the order they are listed to users."""
    return list(CURVES)


def get_curve(name: str) -> Curve:
    """The curve called ``name`` (case-insensitive; ``_`` and ``-`` are interchangeable)."""
    key = str(name).strip().lower().replace("_", "-")
    if key not in CURVES:
        raise ToneError(f"unknown tone curve {name!r}; valid curves: {', '.join(CURVES)}")
    return CURVES[key]


def describe_curves() -> str:
    """A plain-text listing of every curve: summary and parameters with ranges and defaults."""
    lines = []
    for c in CURVES.values():
        lines.append(f"{c.name:<18s} {c.summary}")
        for p in c.params:
            lines.append(f"{'':<20s}{p.describe()}")
    return "\n".join(lines)


# ---------------------------------------------------------------------------------------------
# Kernels. A kernel is ``k(src, dst, scratch)`` on 1-D float32 blocks (or (n, 3) for "rgb" curves):
# src holds repaired values >= 0 with no inf (src may be dst), scratch is a list of two float32
# buffers of the block's shape. Exposure is folded in: each builder gets ``scale = 2**EV``.


def _build_clamp(p, scale):
    s = F32(scale)

    def k(src, dst, scratch):
        if s != 1:
            np.multiply(src, s, out=dst)
            src = dst
        _clip(src, F32(0), F32(1), out=dst)
    return k


# The sRGB EOTF (IEC 61966-2-1, as colour-science's ``eotf_sRGB`` defines it): v / 12.92 up to
# v = 0.04045, ((v + 0.055) / 1.055)^2.4 above
_SRGB_KNEE, _SRGB_SLOPE, _SRGB_OFFSET, _SRGB_POWER = 0.04045, 12.92, 0.055, 2.4
# smallest input the gamma kernel takes the log of: float32 log2 and exp2 run at full SIMD speed only
# away from 0 (log2(0) = -inf) and from denormal results (exp2 below -126), which cost 10 to 100 times more
_LOG2_FLOOR = -126.0


def _gamma_steps(values: np.ndarray, scale, inv: np.float32, floor: np.float32) -> np.ndarray:
    """v = min(x, 1)^(1/gamma) as the kernel computes it: exp2(log2(clip(s x, floor, 1)) / gamma)."""
    v = np.multiply(values, F32(scale), dtype=F32) if scale != 1 else values.astype(F32, copy=True)
    _clip(v, floor, F32(1), out=v)
    np.log2(v, out=v)
    v *= inv
    np.exp2(v, out=v)
    return v


def _srgb_power_steps(v: np.ndarray, out: np.ndarray, gain) -> np.ndarray:
    """The power segment of the sRGB EOTF on max(v, knee), as the kernel computes it (in float32:
    gain exp2(2.4 log2(u + 0.055)), gain = 1.055^-2.4 to an ulp; every step monotone)."""
    _clip(v, F32(_SRGB_KNEE), F32(1), out=out)
    out += F32(_SRGB_OFFSET)
    np.log2(out, out=out)
    out *= F32(_SRGB_POWER)
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
    knee_lin = F32(_SRGB_KNEE) - v0
    slope = F32(_SRGB_KNEE / _SRGB_SLOPE / float(knee_lin))
    # 1.055^-2.4 rounded to float32, nudged by an ulp or two so that x >= 1 gives exactly 1
    gain = F32((1.0 + _SRGB_OFFSET) ** -_SRGB_POWER)
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
        _clip(src, floor, F32(1), out=dst)
        np.log2(dst, out=dst)                  # v = exp2(log2(x) / gamma)
        dst *= inv
        np.exp2(dst, out=dst)
        _srgb_power_steps(dst, a, gain)        # the power segment past the knee ...
        a -= p_knee
        dst -= v0                              # ... plus the linear one below it
        _clip(dst, F32(0), knee_lin, out=dst)
        dst *= slope
        dst += a
        if clip_top:
            _clip(dst, F32(0), F32(1), out=dst)
    return k


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
    return _rational_kernel(s * s / white**2, s, 0.0, s, white / s)


def _rational_kernel(a1, a0, b1, b0, cap):
    """y = x (a1 x + a0) / (x (b1 x + b0) + 1) on min(x, cap), clipped to [0, 1].

    Evaluated as 1 / y = b1/a1 + m / (a1 x + a0) + 1 / (x (a1 x + a0)), m = b0 - b1 a0 / a1 >= 0:
    every step is a rounded monotone operation, so the float32 result never steps back (the plain
    ratio of two increasing polynomials wobbles by an ulp), and x = 0 gives 1/inf = exactly 0.
    """
    m = b0 - b1 * a0 / a1
    if a1 <= 0 or a0 < 0 or b1 < 0 or m < 0:  # pragma: no cover - the curves' parameters rule this out
        raise ToneError("internal: rational curve coefficients are not of the monotone form")
    a1, a0, k, m, cap = F32(a1), F32(a0), F32(b1 / a1), F32(m), F32(cap)

    def k_(src, dst, scratch):
        t, u = scratch
        _clip(src, F32(0), cap, out=dst)
        np.multiply(dst, a1, out=t)
        t += a0
        np.multiply(dst, t, out=u)
        np.divide(F32(1), u, out=u)
        np.divide(m, t, out=t)
        t += u
        t += k
        np.divide(F32(1), t, out=dst)
        _clip(dst, F32(0), F32(1), out=dst)
    return k_


HABLE_PRESETS = {
    # Hable's blog post "Filmic Tonemapping Operators" (2010): the seed's constants
    "blog": dict(A=0.15, B=0.50, C=0.10, D=0.20, E=0.02, F=0.30),
    # Hable's GDC 2010 slides "Uncharted 2: HDR Lighting"
    "gdc": dict(A=0.22, B=0.30, C=0.10, D=0.20, E=0.01, F=0.30),
}


def _hable_constants(p) -> dict:
    const = dict(HABLE_PRESETS[p["preset"]])
    for key in "ABCDEF":
        if p.get(key) is not None:
            const[key] = float(p[key])
    return const


def _hable_check(p: dict) -> dict:
    c = _hable_constants(p)
    A, B, C, D, E, F = (c[k] for k in "ABCDEF")
    # f(x) - f(0) = x (A(F-E) x + B(CF-E)) / (F (A x^2 + B x + DF)); its slope has the numerator
    # AB(1-C) x^2 + 2AD(F-E) x + BD(CF-E), non-negative for every x >= 0 iff C <= 1 and E <= CF.
    if E > C * F + 1e-12:
        raise ToneError(f"curve 'hable': E={E:g} must not exceed C*F={C * F:g}, or the curve dips below 0 "
                        "and is not monotonic; lower E or raise C or F")
    if A * (F - E) <= 0 and B * (C * F - E) <= 0:
        raise ToneError("curve 'hable': the constants make the curve flat (A(F-E) and B(CF-E) both 0); "
                        "keep E below F")
    return p


_CROSS_CHECKS["hable"] = _hable_check


def _hable_coefficients(p, scale=1.0):
    """(a1, a0, b1, b0, cap) of the rational kernel equal to hable at input ``x * scale``."""
    c = _hable_constants(p)
    A, B, C, D, E, F = (c[k] for k in "ABCDEF")
    P, Q, R = A * (F - E) / F, B * (C * F - E) / F, D * F  # f(v) - f(0) = v (P v + Q) / (A v^2 + B v + R)
    white = p["white"]
    g_white = white * (P * white + Q) / (white * (A * white + B) + R)
    k = p["exposure_bias"] * scale
    return (P * k * k / (R * g_white), Q * k / (R * g_white), A * k * k / R, B * k / R, white / k)


def _build_hable(p, scale):
    return _rational_kernel(*_hable_coefficients(p, scale))


_ACES = dict(a=2.51, b=0.03, c=2.43, d=0.59, e=0.14)


def _build_aces(p, scale):
    a, b, c, d, e = (_ACES[k] for k in "abcde")
    # the fit passes 1 where (a-c) x^2 + (b-d) x - e = 0 (x ~ 7.24); capping the input past that point
    # changes nothing after the clamp and keeps x^2 finite
    x1 = ((d - b) + math.sqrt((b - d) ** 2 + 4 * (a - c) * e)) / (2 * (a - c))
    s = scale
    return _rational_kernel(a * s * s / e, b * s / e, c * s * s / e, d * s / e, 2 * x1 / s)


# Stephen Hill's fit (BakingLab, ACES.hlsl): sRGB -> XYZ -> D65->D60 -> AP1 -> RRT_SAT, and back
ACES_HILL_INPUT = np.array([[0.59719, 0.35458, 0.04823],
                            [0.07600, 0.90834, 0.01566],
                            [0.02840, 0.13383, 0.83777]])
ACES_HILL_OUTPUT = np.array([[1.60475, -0.53108, -0.07367],
                             [-0.10208, 1.10813, -0.00605],
                             [-0.00327, -0.07276, 1.07602]])


def _build_aces_hill(p, scale):
    m_in = (ACES_HILL_INPUT * scale).astype(F32)
    m_out = ACES_HILL_OUTPUT.astype(F32)

    def k(src, dst, scratch):  # planar (3, n) blocks
        v, t = scratch
        np.matmul(m_in, src, out=v)
        _clip(v, F32(0), _BIG, out=v)
        # RRTAndODTFit: (v (v + 0.0245786) - 0.000090537) / (v (0.983729 v + 0.4329510) + 0.238081)
        np.multiply(v, F32(0.983729), out=t)
        t += F32(0.4329510)
        t *= v
        t += F32(0.238081)
        np.add(v, F32(0.0245786), out=dst)  # src is no longer needed: dst serves as scratch
        dst *= v
        dst -= F32(0.000090537)
        np.divide(dst, t, out=v)
        np.matmul(m_out, v, out=dst)
        _clip(dst, F32(0), F32(1), out=dst)
    return k


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


def _agx_power_offset(dtype) -> float:
    """The value the 2.2 power gives at its floor, computed with the same steps as the kernels."""
    f = np.full(16, _AGX_POWER_FLOOR, dtype)
    np.log2(f, out=f)
    f *= dtype(2.2)
    np.exp2(f, out=f)
    return dtype(f[0])


def _build_agx(p, scale):
    m_in = (AGX_INSET * scale).astype(F32)
    m_out = AGX_OUTSET.astype(F32)
    # the log2 encoding t = (log2 v - min) / span, clipped to [0, 1]: v is clipped to the encoding's
    # range first, so that t = log2(v) / span - min / span needs no second clip (to an ulp)
    v_lo, v_hi = F32(2.0 ** AGX_MIN_EV), F32(2.0 ** AGX_MAX_EV)
    k, c = F32(1.0 / (AGX_MAX_EV - AGX_MIN_EV)), F32(-AGX_MIN_EV / (AGX_MAX_EV - AGX_MIN_EV))
    floor, offset = F32(_AGX_POWER_FLOOR), _agx_power_offset(F32)

    def k_(src, dst, scratch):  # planar (3, n) blocks
        v, t = scratch
        np.matmul(m_in, src, out=v)
        _clip(v, v_lo, v_hi, out=v)
        np.log2(v, out=v)
        v *= k
        v += c
        np.multiply(v, F32(AGX_POLY[0]), out=t)   # Horner: the 6th-order fit of the AgX sigmoid
        for coef in AGX_POLY[1:-1]:
            t += F32(coef)
            t *= v
        t += F32(AGX_POLY[-1])
        np.matmul(m_out, t, out=dst)
        # the sigmoid's output is display-encoded with a 2.2 power: y = v^2.2 = exp2(2.2 log2 v)
        _clip(dst, floor, F32(1), out=dst)
        np.log2(dst, out=dst)
        dst *= F32(2.2)
        np.exp2(dst, out=dst)
        dst -= offset                              # exactly 0 where the sigmoid is at or below 0
    return k_


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
            _clip(dst, F32(0), _BIG, out=dst)
            x = dst
        # toe offset: low - 6.25 low^2 below 0.08, else 0.04 (= the same expression at low = 0.08)
        np.fmin(np.fmin(x[0], x[1], out=low), x[2], out=low)
        _clip(low, F32(0), F32(0.08), out=low)
        np.multiply(low, F32(-6.25), out=h)
        h += F32(1)
        low *= h
        np.subtract(x, low, out=dst)
        np.fmax(np.fmax(dst[0], dst[1], out=peak), dst[2], out=peak)
        # shoulder on the peak: below `start` the factors below are exactly 1 and 0
        _clip(peak, F32(start), _BIG, out=peak)
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
        _clip(dst, F32(0), F32(1), out=dst)
    return k


def _build_aces_hill_grey(p, scale):
    """The Hill fit on grey (its matrices are the identity on grey to 5 digits), in a form whose every
    step is monotone: 1 / fit = c + m / (v + p - q/v) + n / (v (v + p - q/v)), m = d - c p, n = e + c q;
    where v + p - q/v <= 0 the fit is <= 0 and the result 0."""
    s = F32(scale)
    pp, q, c, d, e = 0.0245786, 0.000090537, 0.983729, 0.4329510, 0.238081
    m, n = F32(d - c * pp), F32(e + c * q)

    def k(src, dst, scratch):
        a, u = scratch
        np.multiply(src, s, out=dst)
        _clip(dst, F32(0), _BIG, out=dst)
        np.divide(F32(q), dst, out=a)
        np.subtract(dst, a, out=a)
        a += F32(pp)
        _clip(a, _TINY, _FMAX, out=a)       # a = v + p - q/v
        np.multiply(dst, a, out=u)           # u = v a = v (v + p) - q
        np.divide(n, u, out=u)
        np.divide(m, a, out=a)
        a += u
        a += F32(c)
        np.divide(F32(1), a, out=dst)
        _clip(dst, F32(0), F32(1), out=dst)
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
        _clip(dst, F32(0), _BIG, out=dst)
        _clip(dst, F32(0), F32(0.08), out=a)
        a *= a
        a *= F32(6.25)
        dst -= F32(0.04)
        np.fmax(dst, a, out=dst)                 # z
        _clip(dst, F32(start), _BIG, out=a)
        a += F32(d - start)
        np.divide(F32(-d * d), a, out=a)
        a -= at_start                            # s(max(z, start)) - s(start), exactly 0 at start
        _clip(dst, F32(0), F32(start), out=dst)
        dst += a
        _clip(dst, F32(0), F32(1), out=dst)
    return k


def _build_agx_grey(p, scale):
    """AgX on grey: the sigmoid of the log2 encoding and the 2.2 power, without the inset and outset
    matrices (the identity on grey to 4 digits), in float64 so that rounding cannot reverse the order
    of two neighbouring inputs once the result is rounded to float32."""
    lo, span = AGX_MIN_EV, AGX_MAX_EV - AGX_MIN_EV
    offset = _agx_power_offset(np.float64)

    def k(src, dst, scratch):
        v = src.astype(np.float64) * scale
        _clip(v, 1e-10, 1e15, out=v)
        np.log2(v, out=v)
        v -= lo
        v /= span
        _clip(v, 0.0, 1.0, out=v)
        t = np.full_like(v, AGX_POLY[0])
        for coef in AGX_POLY[1:]:
            t *= v
            t += coef
        _clip(t, _AGX_POWER_FLOOR, 1.0, out=t)
        np.log2(t, out=t)
        t *= 2.2
        np.exp2(t, out=t)
        t -= offset                          # exactly 0 where the sigmoid is at or below 0
        dst[...] = t
    return k


def _grey_kernel(rgb_kernel, weights):
    """The scalar form of an RGB curve: run it on (x, x, x), weigh the result to one value."""
    w = np.asarray(weights, dtype=F32)

    def k(src, dst, scratch):
        grey = np.broadcast_to(src, (3, src.size))
        out = np.empty((3, src.size), F32)
        rgb_kernel(grey, out, [np.empty_like(out), np.empty_like(out)])
        np.matmul(w, out, out=dst)
        _clip(dst, F32(0), F32(1), out=dst)
    return k


# ---------------------------------------------------------------------------------------------
# Colour helpers: luminance weights, log-averages, automatic exposure


@functools.lru_cache(maxsize=32)
def _weights_by_name(name: str) -> tuple[float, float, float]:
    import colour

    if name not in colour.RGB_COLOURSPACES:
        close = [n for n in colour.RGB_COLOURSPACES if name.lower() in n.lower()][:8]
        hint = f" (close: {', '.join(close)})" if close else " such as sRGB, ITU-R BT.2020, ACEScg, Display P3"
        raise ToneError(f"unknown RGB colourspace {name!r} for luminance weights; use a colour-science "
                        f"colourspace name{hint}")
    return tuple(float(v) for v in colour.RGB_COLOURSPACES[name].matrix_RGB_to_XYZ[1])


def luminance_weights(primaries="sRGB") -> np.ndarray:
    """Luminance weights (Y row of RGB -> XYZ) from colour-science, float32 (3,).

    ``primaries``: a colour-science colourspace name (``"sRGB"``: Rec.709, 0.2126 0.7152 0.0722),
    chromaticities ``((xr, yr), (xg, yg), (xb, yb), (xw, yw))`` as an EXR header stores them, or
    three weights directly.
    """
    if primaries is None:
        primaries = "sRGB"
    if isinstance(primaries, str):
        return np.array(_weights_by_name(primaries), dtype=F32)
    arr = np.asarray(primaries, dtype=np.float64)
    if arr.shape == (3,):
        w = arr
    elif arr.shape == (4, 2):
        import colour

        w = colour.normalised_primary_matrix(arr[:3], arr[3])[1]
    else:
        raise ToneError(f"primaries must be a colourspace name, 4 (x, y) chromaticities or 3 weights; "
                        f"got shape {arr.shape}")
    if not np.all(np.isfinite(w)) or np.any(w < 0) or w.sum() <= 0:
        raise ToneError(f"luminance weights {w.tolist()} are not usable: they must be finite and >= 0")
    return w.astype(F32)


def _luminance_sample(image: np.ndarray, weights, max_samples: int = 1 << 18) -> np.ndarray:
    """Luminance of (an evenly strided sample of) the image, float64, bad values as in tonemap
    (NaN and negatives count as 0, pixels with a +inf channel are dropped)."""
    x = np.asarray(image)
    if x.ndim == 3 and x.shape[-1] in (2, 4):
        x = x[..., :-1]
    channels = 3 if x.ndim == 3 and x.shape[-1] == 3 else 1
    px = x.reshape(-1, channels)
    step = max(1, -(-px.shape[0] // max_samples))
    planes = np.array(px[::step].T, dtype=np.float64)  # (channels, n): contiguous rows
    finite = np.ones(planes.shape[1], bool)
    for row in planes:
        finite &= ~np.isposinf(row)
    np.nan_to_num(planes, copy=False, nan=0.0, posinf=0.0, neginf=0.0)
    np.clip(planes, 0.0, None, out=planes)
    if channels == 3:
        w = np.asarray(weights, dtype=np.float64)
        lum = planes[0] * w[0] + planes[1] * w[1] + planes[2] * w[2]
    else:
        lum = planes[0]
    return lum[finite]


def log_average(lum: np.ndarray, trim: float = 0.0, delta: float | None = None) -> float:
    """Log-average (geometric mean) of luminance values.

    ``delta=None``: over the positive values only, with the ``trim`` percent darkest and brightest of
    them left out (0 when there are none). ``delta > 0``: Reinhard et al.'s ``exp(mean(log(delta + L)))``
    over every value.
    """
    lum = np.asarray(lum, dtype=np.float64).reshape(-1)
    if delta is not None:
        return float(np.exp(np.mean(np.log(delta + lum)))) if lum.size else 0.0
    logs = np.log2(lum[lum > 0])
    if logs.size == 0:
        return 0.0
    if trim > 0:
        lo, hi = np.percentile(logs, [trim, 100.0 - trim])
        kept = logs[(logs >= lo) & (logs <= hi)]
        logs = kept if kept.size else logs
    return float(2.0 ** np.mean(logs))


def auto_exposure(image, key: float = MIDDLE_GREY, trim: float = 1.0, primaries="sRGB") -> float:
    """Exposure in stops that brings the image's log-average luminance to ``key`` (middle grey).

    The average is taken over positive pixels (black borders, e.g. outside a fisheye circle, are
    not scene content), with the ``trim`` percent darkest and brightest left out: a small sun of
    30000 does not drag the rest into black. An image with no positive pixel gets 0 (it stays black).
    The result is limited to :data:`EXPOSURE_RANGE`.
    """
    if not 0 <= trim < 50:
        raise ToneError(f"auto exposure: trim={trim:g} must be a percentage in [0, 50)")
    if not key > 0:
        raise ToneError(f"auto exposure: key={key:g} must be > 0 (middle grey is 0.18)")
    x = np.asarray(image)
    colour_image = x.ndim == 3 and x.shape[-1] in (3, 4)
    avg = log_average(_luminance_sample(x, luminance_weights(primaries) if colour_image else None), trim=trim)
    if avg <= 0:
        return 0.0
    return float(np.clip(math.log2(key / avg), *EXPOSURE_RANGE))


def _parse_exposure(exposure, image, primaries) -> float:
    if isinstance(exposure, str):
        text = exposure.strip().lower()
        if text == "auto":
            return auto_exposure(image, primaries=primaries)
        try:
            exposure = float(text)
        except ValueError:
            raise ToneError(f"exposure {exposure!r} is neither a number of stops nor 'auto'") from None
    try:
        ev = float(exposure)
    except (TypeError, ValueError):
        raise ToneError(f"exposure {exposure!r} is neither a number of stops nor 'auto'") from None
    if not EXPOSURE_RANGE[0] <= ev <= EXPOSURE_RANGE[1]:
        raise ToneError(f"exposure {ev:g} stops is out of range; give a number in "
                        f"[{EXPOSURE_RANGE[0]:g}, {EXPOSURE_RANGE[1]:g}] or 'auto'")
    return ev


# ---------------------------------------------------------------------------------------------
# The sweep: repair, expose and map an image block by block


class _Counts:
    __slots__ = ("nan", "posinf", "negative")

    def __init__(self):
        self.nan = self.posinf = self.negative = 0

    def any(self) -> bool:
        return bool(self.nan or self.posinf or self.negative)


def _repair(block: np.ndarray, counts: _Counts) -> np.ndarray:
    """Repair a block in place (NaN, negatives -> 0; +inf -> 0 for now); return the +inf mask."""
    nan = np.isnan(block)
    posinf = np.isposinf(block)
    neg = block < 0
    counts.nan += int(np.count_nonzero(nan))
    counts.posinf += int(np.count_nonzero(posinf))
    counts.negative += int(np.count_nonzero(neg))
    block[nan | posinf | neg] = 0
    return posinf


_FIRST_NOT_CLEAN = np.uint32(0x7F800000)  # +inf's bits; NaN lie above, negatives (sign bit set) far above


def _clean(block: np.ndarray) -> bool:
    """True when every float32 value is finite and >= +0, tested in one sweep on the bit patterns."""
    return bool(block.view(np.uint32).max() < _FIRST_NOT_CLEAN)


def _sweep_values(flat: np.ndarray, out: np.ndarray, kernel, counts: _Counts) -> None:
    """Per-value curve over 1-D float32 ``flat`` into ``out`` (may be the same array)."""
    n = flat.size
    scratch = [np.empty(min(_BLOCK, n), F32) for _ in range(2)]
    for s in range(0, n, _BLOCK):
        e = min(s + _BLOCK, n)
        src, dst = flat[s:e], out[s:e]
        inf_mask = None
        if not _clean(src):
            if dst is not src:
                np.copyto(dst, src)
            inf_mask = _repair(dst, counts)
            src = dst
        kernel(src, dst, [t[: e - s] for t in scratch])
        if inf_mask is not None:
            dst[inf_mask] = 1


def _sweep_rgb(px: np.ndarray, out: np.ndarray, kernel, counts: _Counts) -> None:
    """RGB curve over (n, 3) float32 pixels into ``out``; a pixel with a +inf channel becomes white.
    Kernels see planar (3, m) blocks: contiguous rows keep every ufunc on the fast path."""
    n = px.shape[0]
    step = _BLOCK // 3
    planes = [np.empty((3, min(step, n)), F32) for _ in range(4)]
    for s in range(0, n, step):
        e = min(s + step, n)
        m = e - s
        src, dst = px[s:e], out[s:e]
        pin, pout, t1, t2 = (p[:, :m] for p in planes)
        np.copyto(pin, src.T)
        inf_cols = None
        if not _clean(pin):
            inf_cols = _repair(pin, counts).any(axis=0)
        kernel(pin, pout, [t1, t2])
        if inf_cols is not None:
            pout[:, inf_cols] = 1
        for c in range(3):
            dst[:, c] = pout[c]


def _sweep_luminance(px: np.ndarray, out: np.ndarray, kernel, weights, counts: _Counts) -> None:
    """Curve on luminance, RGB scaled by curve(L)/L; over-range pixels blended toward grey.

    One planar copy of each block (contiguous rows keep every ufunc on its fast path); the scaling
    and the blend toward grey are one multiply-add per channel with per-pixel factors."""
    n = px.shape[0]
    step = _BLOCK // 3
    size = min(step, n)
    w = np.asarray(weights, dtype=F32).reshape(1, 3)
    pl = np.empty((3, size), F32)
    lum, mapped, ratio, peak = (np.empty(size, F32) for _ in range(4))
    scratch = [np.empty(size, F32) for _ in range(2)]
    big = _FMAX
    for s in range(0, n, step):
        e = min(s + step, n)
        m = e - s
        src, dst = px[s:e], out[s:e]
        p = pl[:, :m]
        np.copyto(p, src.T)
        L, Ld, r, pk = lum[:m], mapped[:m], ratio[:m], peak[:m]
        inf_cols = None
        if not _clean(p):
            inf_cols = _repair(p, counts).any(axis=0)
        np.fmax(p[0], p[1], out=pk)
        np.fmax(pk, p[2], out=pk)               # the brightest channel
        np.matmul(w, p, out=L[None])
        kernel(L, Ld, [t[:m] for t in scratch])
        L += _TINY                              # exact above 1e-30; curve(0) = 0: black gets ratio 0
        np.divide(Ld, L, out=r)
        pk *= r                                 # the brightest channel after scaling
        if pk.max() > 1:
            # blend toward grey (Ld, Ld, Ld) until the peak fits: out = Ld + (p r - Ld) t with
            # t = (1 - Ld) / (peak - Ld) clipped to [0, 1], i.e. p (r t) + Ld (1 - t) in one sweep
            # (t = 1, offset exactly 0, wherever the peak is within range)
            t, b = scratch[0][:m], scratch[1][:m]
            pk -= Ld
            _clip(pk, _TINY, big, out=pk)
            np.subtract(F32(1), Ld, out=t)
            t /= pk
            _clip(t, F32(0), F32(1), out=t)
            r *= t
            np.multiply(Ld, t, out=b)
            np.subtract(Ld, b, out=b)
            p *= r
            p += b
            _clip(p, F32(0), F32(1), out=p)
        else:
            p *= r
        if inf_cols is not None:
            p[:, inf_cols] = 1
        for c in range(3):
            dst[:, c] = p[c]


def _warn(counts: _Counts, total: int) -> None:
    if not counts.any():
        return
    parts = []
    if counts.nan:
        parts.append(f"{counts.nan} NaN set to 0")
    if counts.posinf:
        parts.append(f"{counts.posinf} +inf set to white")
    if counts.negative:
        parts.append(f"{counts.negative} negative set to 0")
    msg = f"tone mapping repaired {', '.join(parts)} (of {total} values)"
    warnings.warn(ToneWarning(msg, counts.nan, counts.posinf, counts.negative, total), stacklevel=3)


def _as_float32(image) -> np.ndarray:
    x = np.asarray(image)
    if x.dtype != F32:
        x = x.astype(F32)
    return np.ascontiguousarray(x)


def tonemap(image, curve: str = "hable", exposure: float | str = 0.0, mode: str = "per-channel",
            *, primaries="sRGB", **params) -> np.ndarray:
    """Tone-map scene-linear ``image`` to display-linear float32 in [0, 1] (same shape).

    ``image``: H x W x C (C = 1, 3; 2 or 4 with alpha last, colour premultiplied as in OpenEXR:
    the curve acts on the unpremultiplied colour and alpha passes through clipped to [0, 1]), or any
    array of single-channel values. ``curve``: a name in :data:`CURVES`. ``exposure``: stops, or
    ``"auto"``. ``mode``: ``"per-channel"`` or ``"luminance"``. ``primaries``: for the luminance
    weights (see :func:`luminance_weights`). ``params``: the curve's parameters.
    Bad values are repaired and reported with a :class:`ToneWarning`.
    """
    spec = get_curve(curve)
    resolved = spec.resolve(params)
    mode_key = str(mode).strip().lower()
    if mode_key not in ("per-channel", "luminance"):
        raise ToneError(f"tone mode {mode!r} is not valid; use 'per-channel' or 'luminance'")
    x = _as_float32(image)
    if x.ndim == 3 and x.shape[-1] not in (1, 2, 3, 4):
        raise ToneError(f"image has {x.shape[-1]} channels; tone mapping takes 1 or 3 (plus alpha)")
    if x.ndim == 3 and x.shape[-1] in (2, 4):
        alpha = np.clip(np.nan_to_num(x[..., -1], nan=0.0, posinf=1.0, neginf=0.0), 0, 1)
        colour_part = x[..., :-1].copy()
        a = alpha[..., None]
        np.divide(colour_part, a, out=colour_part, where=a > 0)
        mapped = tonemap(colour_part, spec.name, exposure, mode_key, primaries=primaries, **resolved)
        mapped *= a
        return np.concatenate([mapped, alpha[..., None].astype(F32)], axis=-1)

    ev = _parse_exposure(exposure, x, primaries)
    scale = 2.0 ** ev
    rgb = x.ndim == 3 and x.shape[-1] == 3
    # luminance weights only where something weighs channels (importing colour-science takes a while)
    needs_weights = spec.kind in ("rgb", "local") or (rgb and (mode_key == "luminance" or spec.kind == "image"))
    weights = luminance_weights(primaries) if needs_weights else None
    counts = _Counts()

    if spec.kind == "local":
        from lenslab import tone_local

        clean = x.copy()
        inf_mask = _repair(clean, counts)
        clean *= F32(scale)
        out = tone_local.apply(spec.name, clean, resolved, weights)
        out[inf_mask.any(axis=-1) if rgb else inf_mask] = 1
        _warn(counts, x.size)
        return out

    if spec.kind == "image":
        # Reinhard et al. 2002: the scale key / log-average comes from the image's luminance
        lum = _luminance_sample(x, weights) * scale
        avg = log_average(lum, delta=resolved["delta"]) if lum.size else 1.0
        scale = scale * resolved["key"] / max(avg, 1e-30)

    out = np.empty_like(x)
    with np.errstate(divide="ignore", over="ignore"):
        _apply_global(spec, resolved, scale, x, out, rgb, mode_key, weights, counts)
    _warn(counts, x.size)
    return out


def _apply_global(spec, resolved, scale, x, out, rgb, mode_key, weights, counts):
    if spec.kind == "rgb":
        rgb_kernel = spec.build(resolved, scale)
        if rgb and mode_key == "per-channel":
            _sweep_rgb(x.reshape(-1, 3), out.reshape(-1, 3), rgb_kernel, counts)
        else:
            grey = spec.build_grey(resolved, scale) if spec.build_grey else _grey_kernel(rgb_kernel, weights)
            if rgb:
                _sweep_luminance(x.reshape(-1, 3), out.reshape(-1, 3), grey, weights, counts)
            else:
                _sweep_values(x.reshape(-1), out.reshape(-1), grey, counts)
    else:
        kernel = spec.build(resolved, scale)
        if rgb and mode_key == "luminance":
            _sweep_luminance(x.reshape(-1, 3), out.reshape(-1, 3), kernel, weights, counts)
        else:
            _sweep_values(x.reshape(-1), out.reshape(-1), kernel, counts)


def _values(curve: str, x, params) -> np.ndarray:
    arr = _as_float32(x)
    out = tonemap(arr.reshape(-1), curve, 0.0, "per-channel", **params)
    return out.reshape(arr.shape)


def _triples(curve: str, x, params) -> np.ndarray:
    arr = _as_float32(x)
    if arr.ndim >= 1 and arr.shape[-1] == 3:
        return tonemap(arr.reshape(-1, 1, 3), curve, 0.0, "per-channel", **params).reshape(arr.shape)
    return _values(curve, arr, params)


# ---------------------------------------------------------------------------------------------
# The curves. Each docstring states the formula and its source; the first line is the summary.

_GAMMA_P = (Param("gamma", 2.2, "display gamma", 0.1, 10.0),)


@_register("clamp", "scalar", build=_build_clamp)
def clamp(x) -> np.ndarray:
    """Clip to white: y = min(x, 1). The seed's original behaviour: every value above 1 is lost."""
    return _values("clamp", x, {})


@_register("gamma", "scalar", _GAMMA_P, build=_build_gamma)
def gamma(x, gamma: float = 2.2) -> np.ndarray:
    """Plain display gamma: code value v = min(x, 1)^(1/gamma) instead of the sRGB curve.

    Returned display-linear as y = sRGB_EOTF(v) (IEC 61966-2-1 as colour-science defines it,
    evaluated in closed form to float32 rounding), so that the sRGB encoding done when writing yields
    v, as renderers that write ``pow(c, 1/2.2)`` do. Exactly 0 at 0 and exactly 1 from x = 1 up.
    """
    return _values("gamma", x, {"gamma": gamma})


@_register("reinhard", "scalar", build=_build_reinhard)
def reinhard(x) -> np.ndarray:
    """Reinhard: y = x / (1 + x). Reinhard et al., "Photographic Tone Reproduction for Digital
    Images", SIGGRAPH 2002, eq. 3. Never reaches 1."""
    return _values("reinhard", x, {})


@_register("reinhard-extended", "scalar",
           (Param("white", 4.0, "input that maps to white (Lw)", 0.0, 1e6, low_open=True),),
           build=_build_reinhard_ext)
def reinhard_extended(x, white: float = 4.0) -> np.ndarray:
    """Reinhard with a white point: y = min(x (1 + x / Lw^2) / (1 + x), 1); y(Lw) = 1.

    Reinhard et al. 2002, eq. 4 (Lw = ``white``).
    """
    return _values("reinhard-extended", x, {"white": white})


def _build_reinhard2002(p, scale):
    if math.isinf(p["white"]):
        return _build_reinhard(p, scale)
    return _build_reinhard_ext({"white": p["white"]}, scale)


@_register("reinhard2002", "image",
           (Param("key", MIDDLE_GREY, "key value a: the log-average maps here", 0.0, 1.0, low_open=True),
            Param("white", math.inf, "burn-out white Lwhite in scaled units (inf: none)", 0.0, math.inf,
                  low_open=True),
            Param("delta", 1e-4, "delta in the log-average (keeps black pixels finite)", 0.0, 1.0,
                  low_open=True)),
           build=_build_reinhard2002)
def reinhard2002(x, key: float = MIDDLE_GREY, white: float = math.inf, delta: float = 1e-4,
                 log_avg: float | None = None) -> np.ndarray:
    """Reinhard et al. 2002 global operator: L = (a / Lavg) x, Lavg = exp(mean(log(delta + Lw))),
    then y = L (1 + L / Lwhite^2) / (1 + L) (y = L / (1 + L) with white = inf).

    Reinhard, Stark, Shirley, Ferwerda, "Photographic Tone Reproduction for Digital Images",
    SIGGRAPH 2002, eqs. 1-4. The log-average is taken over ``x`` itself (or given as ``log_avg``);
    in :func:`tonemap` it is the image's luminance, so any exposure cancels out.
    """
    arr = _as_float32(x)
    p = CURVES["reinhard2002"].resolve({"key": key, "white": white, "delta": delta})
    if log_avg is None:
        log_avg = log_average(_luminance_sample(arr.reshape(-1), None), delta=p["delta"])
    scale = p["key"] / max(float(log_avg), 1e-30)
    out = np.empty_like(arr)
    counts = _Counts()
    with np.errstate(divide="ignore", over="ignore"):
        _sweep_values(arr.reshape(-1), out.reshape(-1), _build_reinhard2002(p, scale), counts)
    _warn(counts, arr.size)
    return out


_HABLE_P = (
    Param("preset", "blog", "constant set: blog (A=0.15 B=0.50 E=0.02, the seed's) or gdc "
          "(A=0.22 B=0.30 E=0.01)", choices=("blog", "gdc")),
    Param("exposure_bias", 2.0, "input multiplier before the curve", 0.0, 1e3, low_open=True),
    Param("white", 11.2, "linear white W: f(bias x) / f(W), so x = W / bias reaches 1", 0.0, 1e6, low_open=True),
    Param("A", None, "shoulder strength (default from preset)", 0.0, 10.0, low_open=True),
    Param("B", None, "linear strength (default from preset)", 0.0, 10.0, low_open=True),
    Param("C", None, "linear angle (default from preset)", 0.0, 1.0),
    Param("D", None, "toe strength (default from preset)", 0.0, 10.0, low_open=True),
    Param("E", None, "toe numerator (default from preset)", 0.0, 10.0),
    Param("F", None, "toe denominator (default from preset)", 0.0, 10.0, low_open=True),
)


@_register("hable", "scalar", _HABLE_P, build=_build_hable)
def hable(x, **params) -> np.ndarray:
    """Hable / Uncharted 2 filmic: y = min(f(bias x) / f(W), 1), f(x) = (x(Ax+CB)+DE) / (x(Ax+B)+DF) - E/F.

    Defaults are the seed's: bias 2.0, W = 11.2, A=0.15 B=0.50 C=0.10 D=0.20 E=0.02 F=0.30 (John
    Hable, "Filmic Tonemapping Operators", 2010); ``preset="gdc"`` takes the set of his GDC 2010
    talk "Uncharted 2: HDR Lighting" (A=0.22 B=0.30 E=0.01). Every constant is a parameter.
    Evaluated as f(x) - f(0) = x (A(F-E) x + B(CF-E)) / (F (A x^2 + B x + DF)), equal in exact
    arithmetic and exactly 0 at 0 in floating point.
    """
    return _values("hable", x, params)


@_register("aces", "scalar", build=_build_aces)
def aces(x) -> np.ndarray:
    """ACES filmic fit (Narkowicz): y = clamp(x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14), 0, 1).

    Krzysztof Narkowicz, "ACES Filmic Tone Mapping Curve", 2016: a fit of the ACES RRT+ODT luminance
    response, per channel.
    """
    return _values("aces", x, {})


@_register("aces-hill", "rgb", build=_build_aces_hill, build_grey=_build_aces_hill_grey)
def aces_hill(rgb) -> np.ndarray:
    """ACES RRT+ODT fit by Stephen Hill: y = clamp(M_out fit(M_in rgb), 0, 1),
    fit(v) = (v (v + 0.0245786) - 0.000090537) / (v (0.983729 v + 0.4329510) + 0.238081).

    Stephen Hill, BakingLab ``ACES.hlsl`` (2016). M_in: sRGB -> XYZ -> D65-to-D60 -> AP1 -> RRT
    saturation; M_out: ODT saturation -> XYZ -> D60-to-D65 -> sRGB (:data:`ACES_HILL_INPUT`,
    :data:`ACES_HILL_OUTPUT`). Acts on RGB triples; on grey it is the fit alone.
    """
    return _triples("aces-hill", rgb, {})


@_register("agx", "rgb", build=_build_agx, build_grey=_build_agx_grey)
def agx(rgb) -> np.ndarray:
    """AgX: inset matrix, log2 encoding over [-12.47393, 4.026069] EV, the 6th-order sigmoid fit
    15.5t^6 - 40.14t^5 + 31.96t^4 - 6.868t^3 + 0.4298t^2 + 0.1191t - 0.00232, outset matrix, then
    display-linear by the 2.2 power.

    Troy Sobotka's AgX as in Benjamin Wrensch, "Minimal AgX Implementation" (2024), default look.
    Acts on RGB triples.
    """
    return _triples("agx", rgb, {})


@_register("pbr-neutral", "rgb", build=_build_pbr_neutral, build_grey=_build_pbr_neutral_grey)
def pbr_neutral(rgb) -> np.ndarray:
    """Khronos PBR Neutral: linear (after a toe offset) up to 0.76, then a shoulder on the peak
    channel, newPeak = 1 - 0.24^2 / (peak - 0.52), with desaturation 0.15 toward white.

    Khronos Group, "PBR Neutral" tone mapper (2024), reference GLSL. Base colours below the shoulder
    come out as they went in (minus the small toe offset). Acts on RGB triples.
    """
    return _triples("pbr-neutral", rgb, {})


_LOCAL_HEADROOM = Param("headroom", 12.0, "stops above the log-average kept before OpenCV's "
                        "normalisation by the maximum (brighter is clipped)", 1.0, 30.0)


@_register("drago", "local",
           (Param("saturation", 1.0, "colour saturation (OpenCV)", 0.0, 4.0, low_open=True),
            Param("bias", 0.85, "bias of the logarithmic base (Drago: 0.7 to 0.9)", 0.0, 1.0, low_open=True),
            _LOCAL_HEADROOM))
def drago(rgb, saturation: float = 1.0, bias: float = 0.85, headroom: float = 12.0) -> np.ndarray:
    """Drago adaptive logarithmic mapping (OpenCV ``createTonemapDrago``):
    Ld = log(L + 1) / log(2 + 8 (L / Lmax)^(log(bias) / log(0.5))), L relative to the log-average.

    Drago, Myszkowski, Annen, Chiba, "Adaptive Logarithmic Mapping For Displaying High Contrast
    Scenes", Eurographics 2003. Not a per-pixel curve: it depends on the image's maximum and average.
    """
    return tonemap(rgb, "drago", saturation=saturation, bias=bias, headroom=headroom)


@_register("mantiuk", "local",
           (Param("scale", 0.7, "contrast scale factor (lower: stronger compression)", 0.0, 2.0, low_open=True),
            Param("saturation", 1.0, "colour saturation (OpenCV)", 0.0, 4.0, low_open=True),
            _LOCAL_HEADROOM))
def mantiuk(rgb, scale: float = 0.7, saturation: float = 1.0, headroom: float = 12.0) -> np.ndarray:
    """Mantiuk contrast-domain mapping (OpenCV ``createTonemapMantiuk``): contrasts of the log
    luminance pyramid are scaled (``scale``) and the image is rebuilt by conjugate gradients.

    Mantiuk, Myszkowski, Seidel, "A Perceptual Framework for Contrast Processing of High Dynamic
    Range Images", ACM TAP 2006. A local operator: not a per-pixel curve.
    """
    return tonemap(rgb, "mantiuk", scale=scale, saturation=saturation, headroom=headroom)
