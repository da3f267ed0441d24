"""Tone matching: the exposure and curve parameters that make a tone-mapped HDR image reproduce an LDR one.

Given the scene-linear HDR image and a display image of the same scene and size (made by a camera or
another tool, read as linear light), the fit minimises the mean squared difference of the
*sRGB-encoded* values, ``mean((srgb(tonemap(hdr; EV, params)) - srgb(ldr))^2)``, over a fixed,
evenly spread subset of pixels: encoded values are what the LDR file holds and what the eye compares.

Which parameters move: by default the exposure (in stops) and every numeric curve parameter with a
default of its own, except those that only trade places with the exposure (Hable's ``exposure_bias``)
and curves whose scale comes from the image (where the exposure cancels). Hable's shape constants
``A``..``F`` follow the preset unless named in ``free``. Positive parameters with a wide range move
in log scale. Every parameter moves within the box :meth:`lenslab.params.Param.search_bounds`
gives (the same rule as for lens models) unless ``bounds`` says otherwise.

The colour difference is reported before (the curve's defaults, exposure 0) and after the fit as
CIEDE2000 (colour-science ``delta_E(..., method="CIE 2000")``) on CIE Lab of the two images' linear
sRGB values (D65).
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass, field
from typing import Mapping, Sequence

import numpy as np

from lenslab.errors import FitError, FitSpecError, ToneError
from lenslab.fit.digits import significant
from lenslab.fit.optimize import OptimizeResult, minimize
from lenslab.fit.params import parse_bounds, parse_names

MAX_PIXELS = 1 << 16  # pixels the objective looks at (evenly spread over the image)
EXPOSURE_BOUNDS = (-16.0, 16.0)  # stops
NOT_FITTED_BY_DEFAULT = frozenset({"exposure_bias", "delta", "headroom"})


def srgb_encode(x: np.ndarray) -> np.ndarray:
    """Linear values clipped to [0, 1] -> sRGB code values, float64 (:mod:`lenslab.srgb`)."""
    from lenslab import srgb

    return srgb.eotf_inverse(np.clip(x, 0.0, 1.0))


def lab(rgb_linear: np.ndarray) -> np.ndarray:
    """CIE Lab (D65) of linear sRGB values (..., 3)."""
    from lenslab.srgb import colour_science

    colour = colour_science()

    cs = colour.RGB_COLOURSPACES["sRGB"]
    rgb = np.clip(np.asarray(rgb_linear, dtype=np.float64), 0.0, None)
    return colour.XYZ_to_Lab(colour.RGB_to_XYZ(rgb, cs), cs.whitepoint)


def ciede2000(a_linear: np.ndarray, b_linear: np.ndarray) -> np.ndarray:
    """Per-pixel CIEDE2000 between two linear sRGB images (..., 3)."""
    from lenslab.srgb import colour_science

    colour = colour_science()

    return np.asarray(colour.delta_E(lab(a_linear), lab(b_linear), method="CIE 2000"), dtype=np.float64)


def _rgb(image: np.ndarray) -> np.ndarray:
    """(H, W, 3) float64 view of an image with 1..4 channels (grey repeated, alpha dropped)."""
    from lenslab.errors import check_image_shape

    a = np.asarray(check_image_shape(image), dtype=np.float64)
    if a.ndim == 2:
        a = a[..., None]
    c = a.shape[-1]
    a = a[..., :3] if c >= 3 else a[..., :1]
    return np.repeat(a, 3, axis=-1) if a.shape[-1] == 1 else a


def sample_indices(h: int, w: int, n: int = MAX_PIXELS) -> np.ndarray:
    """Flat indices of about ``n`` pixels on a regular grid over an ``h x w`` image (all if fewer)."""
    if h * w <= n:
        return np.arange(h * w)
    step = math.sqrt(h * w / n)
    ny, nx = max(1, int(h / step)), max(1, int(w / step))
    # the centres of ny x nx equal cells: the same margin at both ends of each axis
    ys = np.unique(np.floor((np.arange(ny) + 0.5) * (h / ny)).astype(int).clip(0, h - 1))
    xs = np.unique(np.floor((np.arange(nx) + 0.5) * (w / nx)).astype(int).clip(0, w - 1))
    return (ys[:, None] * w + xs[None, :]).ravel()


@dataclass
class Variable:
    name: str
    start: float
    lo: float
    hi: float
    log: bool  # optimised as log(value)

    def to_opt(self, v: float) -> float:
        return math.log(v) if self.log else v

    def from_opt(self, t: float) -> float:
        return math.exp(t) if self.log else t


@dataclass
class ToneFit:
    """The fitted exposure and curve parameters, and the colour difference before and after."""

    curve: str
    mode: str
    exposure: float
    params: dict[str, float]  # every curve parameter (fixed and fitted)
    free: tuple[str, ...]
    rms_before: float  # RMS difference of sRGB-encoded values, 0..1
    rms_after: float
    delta_e_before: dict[str, float]  # mean, median, p95, max CIEDE2000
    delta_e_after: dict[str, float]
    optimizer: OptimizeResult
    pixels: int
    seconds: float = 0.0
    notes: list[str] = field(default_factory=list)

    def command_line(self) -> str:
        """The ``lenslab tonemap`` options that reproduce the fitted look."""
        from lenslab import tone

        spec = tone.get_curve(self.curve)
        # the values the curve takes when given only the same choices (Hable's preset fills A..F)
        defaults = spec.resolve({p.name: self.params[p.name] for p in spec.params
                                 if p.choices is not None and p.name in self.params})
        parts = [f"--tone {self.curve}", f"--exposure {significant(self.exposure)}"]
        for k, v in self.params.items():
            if k in self.free or (v is not None and v != defaults.get(k)):
                parts.append(f"--param {k}={significant(v)}" if isinstance(v, float) else f"--param {k}={v}")
        if self.mode != "per-channel":
            parts.append(f"--{self.mode}")
        return " ".join(parts)

    def report(self) -> list[str]:
        fitted = ", ".join(f"{k}={significant(v)}" for k, v in [("exposure", self.exposure)] + list(self.params.items())
                           if k == "exposure" and "exposure" in self.free or k in self.free)
        de_b, de_a = self.delta_e_before, self.delta_e_after
        lines = [f"curve:    {self.curve} ({self.mode})",
                 f"fitted:   {fitted or 'nothing'}",
                 f"tonemap:  {self.command_line()}",
                 f"encoded RMS difference: {self.rms_before:.5f} before -> {self.rms_after:.5f} after "
                 f"({self.pixels} pixels)",
                 f"CIEDE2000 before: mean {de_b['mean']:.3f}, median {de_b['median']:.3f}, "
                 f"95% {de_b['p95']:.3f}, max {de_b['max']:.3f}",
                 f"CIEDE2000 after:  mean {de_a['mean']:.3f}, median {de_a['median']:.3f}, "
                 f"95% {de_a['p95']:.3f}, max {de_a['max']:.3f}",
                 f"nlopt:    {self.optimizer.describe()}",
                 f"time:     {self.seconds:.2f} s"]
        lines += [f"note:     {n}" for n in self.notes]
        return lines


def _stats(de: np.ndarray) -> dict[str, float]:
    return {"mean": float(de.mean()), "median": float(np.median(de)), "p95": float(np.percentile(de, 95)),
            "max": float(de.max())}


def _variables(curve, free: Sequence[str] | None, bounds: dict, fixed: dict) -> list[Variable]:
    from lenslab import tone

    spec = tone.get_curve(curve)
    resolved = spec.resolve({k: v for k, v in fixed.items() if k != "exposure"})
    params = {p.name: p for p in spec.params}
    if free is None:
        names = [] if spec.kind == "image" else ["exposure"]
        names += [p.name for p in spec.params
                  if p.choices is None and p.default is not None and p.name not in fixed
                  and p.name not in NOT_FITTED_BY_DEFAULT and math.isfinite(float(p.default))]
    else:
        names = list(free)
    out = []
    for n in names:
        if n == "exposure":
            lo, hi = bounds.get(n, EXPOSURE_BOUNDS)
            out.append(Variable(n, float(fixed.get("exposure", 0.0)), lo, hi, False))
            continue
        if n not in params or params[n].choices is not None:
            numeric = [p.name for p in spec.params if p.choices is None]
            raise FitSpecError(f"curve {spec.name!r} has no numeric parameter {n!r}; its parameters: "
                           f"exposure, {', '.join(numeric)}")
        start = float(resolved[n])  # a value derived from others (Hable's A..F) is resolved too
        lo, hi = bounds[n] if n in bounds else params[n].search_bounds(start)
        log = lo > 0 and hi / lo > 8.0
        out.append(Variable(n, min(max(start, lo), hi), lo, hi, log))
    return out


def tone_variables(curve: str, free, bounds: Mapping[str, tuple[float, float]], fixed: Mapping[str, float]):
    """The curve's record and the variables a tone fit moves, checked before any image is read: a curve,
    parameter, ``free`` name or ``bounds`` that names nothing raises :class:`~lenslab.errors.FitSpecError`
    (a usage error when typed on the command line)."""
    from lenslab import tone

    try:
        spec = tone.get_curve(curve)
        variables = _variables(spec.name, parse_names(free), dict(bounds), dict(fixed))
    except ToneError as exc:
        raise FitSpecError(str(exc)) from None
    names = tuple(v.name for v in variables)
    for n in bounds:
        if n not in names:
            raise FitSpecError(f"bounds given for {n}, which is not fitted; fitted: {', '.join(names) or 'none'}")
    return spec, variables


def fit_tone(
    hdr: np.ndarray,
    ldr: np.ndarray,
    curve: str = "hable",
    *,
    mode: str = "per-channel",
    free: Sequence[str] | str | None = None,
    fixed: Mapping[str, float] | None = None,
    bounds: Mapping[str, tuple[float, float]] | str | None = None,
    global_start: str | None = "auto",
    max_pixels: int = MAX_PIXELS,
) -> ToneFit:
    """Fit exposure and parameters of ``curve`` so that ``tonemap(hdr)`` reproduces ``ldr`` (both linear light).

    Parameters
    ----------
    hdr : numpy.ndarray
        The scene-linear image, ``H x W x 3`` (or grey).
    ldr : numpy.ndarray
        The same view as shown, display-linear (an sRGB file as :func:`lenslab.io.read` decodes it).
    curve : str
        A tone curve of :data:`lenslab.tone.CURVES`.
    mode : str
        ``"per-channel"`` or ``"luminance"``, as :func:`lenslab.tone.tonemap` takes it.
    free : str or sequence of str, optional
        The names to fit (``exposure`` included), replacing the default choice.
    fixed : mapping, optional
        Curve parameters (and ``exposure``) held at given values (also the start of free ones).
    bounds : mapping or str, optional
        Search ranges, ``{"exposure": (-4, 4)}`` or ``"exposure=-4:4"``.
    global_start : str, optional
        As for :func:`~lenslab.fit.lens.fit_lens`.
    max_pixels : int
        Pixels used at most (a regular subsample of larger images).

    Returns
    -------
    ToneFit
        ``exposure``, every curve parameter, and the sRGB RMS and CIEDE2000 differences before and after.

    Raises
    ------
    lenslab.errors.FitError
        Images of different sizes, or an unknown parameter name.
    lenslab.errors.ToneError
        An unknown curve.

    Examples
    --------
    An image shown through Reinhard one stop up gives that stop back:

    >>> import numpy as np, lenslab
    >>> from lenslab.fit import fit_tone
    >>> hdr = np.random.default_rng(1).uniform(0.0, 4.0, (16, 16, 3)).astype(np.float32)
    >>> shown = lenslab.tonemap(hdr, "reinhard", exposure=1.0)
    >>> fit = fit_tone(hdr, shown, "reinhard")
    >>> round(fit.exposure, 6), fit.free, fit.rms_after < 1e-6
    (1.0, ('exposure',), True)
    """
    from lenslab import tone
    from lenslab.tone.repairs import uncounted

    t0 = time.perf_counter()
    fixed = dict(fixed or {})
    bounds = parse_bounds(bounds) if isinstance(bounds, str) or bounds is None else dict(bounds)
    spec, variables = tone_variables(curve, free, bounds, fixed)
    names = tuple(v.name for v in variables)
    a, b = _rgb(hdr), _rgb(ldr)
    if a.shape[:2] != b.shape[:2]:
        raise FitError(f"the HDR image is {a.shape[1]}x{a.shape[0]} but the LDR one is {b.shape[1]}x{b.shape[0]}; "
                       "give two images of the same view and size (resize or crop one first)")
    idx = sample_indices(a.shape[0], a.shape[1], max_pixels)
    x = a.reshape(-1, 3)[idx].astype(np.float32)[:, None, :]  # (n, 1, 3): an image of one column
    target_lin = np.clip(b.reshape(-1, 3)[idx], 0.0, 1.0)
    target = srgb_encode(target_lin)
    base_params = {k: v for k, v in fixed.items() if k != "exposure"}

    def render(values: dict) -> np.ndarray:
        params = dict(base_params)
        params.update({k: v for k, v in values.items() if k != "exposure"})
        ev = values.get("exposure", fixed.get("exposure", 0.0))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", tone.ToneWarning)
            return np.asarray(tone.tonemap(x, spec.name, float(ev), mode, **params), dtype=np.float64)[:, 0, :]

    def values_of(t) -> dict:
        return {v.name: v.from_opt(float(ti)) for v, ti in zip(variables, t)}

    def objective(t) -> float:
        try:
            out = render(values_of(t))
        except ToneError:
            return math.inf  # a combination the curve refuses (e.g. a non-monotonic Hable)
        return float(np.mean((srgb_encode(out) - target) ** 2))

    start = [v.to_opt(v.start) for v in variables]
    lower = [v.to_opt(v.lo) for v in variables]
    upper = [v.to_opt(v.hi) for v in variables]
    before_img = render({})  # the one render whose repairs of the HDR values (slight negatives) are counted
    rms_before = float(np.sqrt(np.mean((srgb_encode(before_img) - target) ** 2)))
    with uncounted():  # every later render repairs the same values again
        res = _run(objective, start, lower, upper, names, global_start)
        fitted = values_of(res.x)
        after_img = render(fitted)
    rms_after = float(np.sqrt(np.mean((srgb_encode(after_img) - target) ** 2)))
    params = spec.resolve({**base_params, **{k: v for k, v in fitted.items() if k != "exposure"}})
    exposure = float(fitted.get("exposure", fixed.get("exposure", 0.0)))
    notes = []
    if not res.converged:
        notes.append("the optimiser did not converge: the values above are the best it found")
    clipped = float(np.mean((target_lin <= 0.0) | (target_lin >= 1.0)))
    if clipped > 0.5:
        notes.append(f"{100 * clipped:.0f}% of the LDR values are clipped to black or white: they carry "
                     "little information about the curve")
    de_after = _stats(ciede2000(after_img, target_lin))
    if de_after["mean"] > MATCHED_DE:
        notes.append(f"the mean CIEDE2000 after the fit is {de_after['mean']:.3g}, far beyond what a tone curve "
                     f"leaves between two pictures of one view (above {MATCHED_DE:g}): check that the two images "
                     "show the same view, aligned, and that the LDR one is sRGB-encoded")
    return ToneFit(spec.name, mode, exposure, params, names, rms_before, rms_after,
                   _stats(ciede2000(before_img, target_lin)), de_after, res, len(idx), time.perf_counter() - t0,
                   notes)


#: a mean CIEDE2000 above this after the fit gets a note: about 1 is a just noticeable difference, so after
#: the best curve the two images still differ plainly (a camera's JPEG of the same view leaves a few)
MATCHED_DE = 10.0


def _run(objective, start, lower, upper, names, global_start) -> OptimizeResult:
    def attempt(g):
        try:
            return minimize(objective, start, lower, upper, names=names, method="bobyqa", global_start=g,
                            stopval=1e-30, ftol_rel=1e-14)
        except FitError as exc:
            if exc.best is not None:
                return exc.best
            raise

    res = attempt(None) if global_start in (None, "auto") else attempt(global_start)
    # an encoded RMS of 1/255 is one 8-bit code: beyond that a local start may have missed the basin
    if global_start == "auto" and res.value > (1.0 / 255) ** 2:
        other = attempt("direct-l")
        if other.value < res.value:
            other.stages = res.stages + other.stages
            other.evaluations += res.evaluations
            res = other
        else:
            res.stages += other.stages
            res.evaluations += other.evaluations
    return res
