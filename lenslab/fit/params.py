"""Which parameters of a lens model a fit moves, where they start, and the box they move in.

A model spec such as ``fisheye:mapping=equisolid`` or ``brown:fov=90`` names the model to fit:

- parameters given in the spec stay fixed at those values;
- the other numeric parameters are fitted (except a few that switch a feature on, like ``vfov``);
- the other choice parameters (like a fisheye's ``mapping``) are tried in turn, and the best kept.

``free=`` names the fitted parameters explicitly; a value the spec gives for one of them is then its
starting point. ``bounds=`` overrides a parameter's range; otherwise it moves within the box
:meth:`lenslab.params.Param.search_bounds` gives (the same rule as for tone curves).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field
from typing import Any, Mapping, Sequence

import numpy as np

from lenslab.errors import FitError, FitSpecError, LensError
from lenslab.lenses import REGISTRY, parse_spec
from lenslab.lenses.core.base import Lens, Param

# float parameters whose default switches a feature off or sets a frame rather than a shape: they
# are fitted only when named in ``free``
NOT_FITTED_BY_DEFAULT = frozenset({"vfov", "dfov", "pad", "lon_min", "lon_max", "lat_min", "lat_max", "cx", "cy"})
#: terms a model carries beyond its plain form (tangential, thin prism, rational): fitted only when named
EXTRA_TERMS = {
    "kannala-brandt": ("p1", "p2", "s1", "s2", "s3", "s4"),
    "opencv-fisheye": ("p1", "p2", "s1", "s2", "s3", "s4"),
    "opencv": ("p1", "p2", "k4", "k5", "k6", "s1", "s2", "s3", "s4"),
}


def parse_bounds(text: str | None) -> dict[str, tuple[float, float]]:
    """``"k1=-1:1,fov=60:120"`` -> ``{"k1": (-1, 1), "fov": (60, 120)}``."""
    out: dict[str, tuple[float, float]] = {}
    if not text:
        return out
    for item in text.split(","):
        name, eq, rng = item.partition("=")
        lo, colon, hi = rng.partition(":")
        try:
            if not (eq and colon and name.strip()):
                raise ValueError
            out[name.strip()] = (float(lo), float(hi))
        except ValueError:
            raise FitSpecError(f"bounds {item!r}: expected NAME=LOW:HIGH, for example k1=-0.5:0.5") from None
    return out


def parse_names(text: str | Sequence[str] | None) -> tuple[str, ...] | None:
    if text is None:
        return None
    if isinstance(text, str):
        return tuple(n.strip() for n in text.split(",") if n.strip())
    return tuple(text)


@dataclass
class ParamSpace:
    """The parameters a fit moves for one model bound to one image size."""

    cls: type
    size: tuple[int, int]
    fixed: dict[str, Any]
    names: tuple[str, ...]
    start: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    choices: dict[str, tuple[str, ...]] = field(default_factory=dict)  # tried in turn
    defaults: np.ndarray | None = None  # the model's own defaults (a second start), within the bounds

    def __post_init__(self):
        if self.defaults is None:
            self.defaults = self.start.copy()

    @property
    def model(self) -> str:
        return self.cls.name

    def combinations(self) -> list[dict[str, str]]:
        """Every assignment of the choice parameters that are tried in turn (one empty dict if none)."""
        keys = list(self.choices)
        return [dict(zip(keys, combo)) for combo in itertools.product(*(self.choices[k] for k in keys))]

    def values(self, x: Sequence[float], combo: Mapping[str, str] | None = None) -> dict[str, Any]:
        vals = dict(self.fixed)
        vals.update(combo or {})
        for name, v in zip(self.names, x):
            vals[name] = float(v)
        return vals

    def make(self, x: Sequence[float], combo: Mapping[str, str] | None = None) -> Lens:
        """The lens with parameters ``x`` (raises LensError where the model refuses them)."""
        return self.cls(self.size[0], self.size[1], **self.values(x, combo))

    def try_make(self, x, combo=None) -> Lens | None:
        try:
            return self.make(x, combo)
        except LensError:
            return None


def model_params(cls: type, given: Mapping[str, Any]) -> list[Param]:
    """The parameters of a model, with those of its base model for the bent ones (swirl, distortion)."""
    out = list(cls.params)
    if any(p.name == "base" for p in out):
        base = str(given.get("base", next(p.default for p in out if p.name == "base"))).strip().lower()
        base_cls = REGISTRY.get(base)
        if base_cls is None:
            raise FitSpecError(f"{cls.name}: unknown base model {base!r}; valid models: {', '.join(sorted(REGISTRY))}")
        names = {p.name for p in out}
        out += [p for p in model_params(base_cls, given) if p.name not in names]
    return out


def build_space(
    model: str,
    size: tuple[int, int],
    *,
    free: Sequence[str] | str | None = None,
    bounds: Mapping[str, tuple[float, float]] | str | None = None,
    start_from: Lens | None = None,
    start_values: Mapping[str, float] | None = None,
) -> ParamSpace:
    """The fit's parameter space for the model spec ``model`` at image size ``size``.

    ``start_from``: a lens whose parameters of the same name (like ``fov``) give starting values; a
    calibrated model's intrinsics the spec does not give follow it instead (its principal point and
    central scale: :func:`lenslab.fit.start.source_start`). ``start_values`` override both.
    """
    name, given = parse_spec(model)
    if name not in REGISTRY:
        raise FitSpecError(f"unknown lens model {name!r}; valid models: {', '.join(sorted(REGISTRY))}")
    cls = REGISTRY[name]
    params = {p.name: p for p in model_params(cls, given)}
    unknown = sorted(set(given) - set(params))
    if unknown:
        raise FitSpecError(f"{name}: unknown parameter(s) {', '.join(unknown)}; valid: {', '.join(params) or 'none'}")
    bounds = parse_bounds(bounds) if isinstance(bounds, str) or bounds is None else dict(bounds)
    free_names = parse_names(free)
    converted = {k: params[k].convert(name, v) for k, v in given.items()}
    numeric = [p for p in params.values() if p.kind is float]
    if free_names is None:
        free_names = tuple(p.name for p in numeric if p.name not in given and p.name not in NOT_FITTED_BY_DEFAULT
                           and p.name not in EXTRA_TERMS.get(name, ()))
    for n in free_names:
        if n not in params:
            raise FitSpecError(f"{name}: cannot fit {n!r}: no such parameter; valid: {', '.join(params)}")
        if params[n].kind is not float:
            raise FitSpecError(f"{name}: parameter {n} is not a real number; give its value in the model spec instead")
    for n in bounds:
        if n not in free_names:
            raise FitSpecError(f"{name}: bounds given for {n}, which is not fitted; "
                               f"fitted: {', '.join(free_names) or 'none'}")
    source_values = start_from.param_values() if start_from is not None else {}
    follow = {}
    if start_from is not None:
        from lenslab.fit.start import source_start

        follow = source_start(cls, start_from, converted)
    follow.update({k: float(v) for k, v in (start_values or {}).items() if k not in converted})
    source_values = {**source_values, **follow}
    start, lower, upper, defaults = [], [], [], []
    for n in free_names:
        p = params[n]
        d = float(converted.get(n, follow.get(n, p.default)))
        if n in converted:
            s = float(converted[n])
        else:
            s = float(p.default)
            sv = source_values.get(n)
            if isinstance(sv, float) and not isinstance(sv, bool):
                try:
                    s = float(p.convert(name, sv))
                except LensError:
                    pass
        lo, hi = bounds.get(n) or p.search_bounds(s)
        if not lo < hi:
            raise FitSpecError(f"{name}: bounds for {n} are empty ({lo:g} >= {hi:g}); give LOW < HIGH")
        s = min(max(s, lo), hi)
        defaults.append(min(max(d, lo), hi))
        start.append(s)
        lower.append(lo)
        upper.append(hi)
    fixed = {k: v for k, v in converted.items() if k not in free_names}
    fixed.update({k: v for k, v in follow.items() if k not in free_names and k in params})
    choices = {p.name: p.choices for p in params.values()
               if p.choices is not None and p.name not in given and len(p.choices) > 1}
    return ParamSpace(cls, (int(size[0]), int(size[1])), fixed, tuple(free_names),
                      np.asarray(start, dtype=np.float64), np.asarray(lower, dtype=np.float64),
                      np.asarray(upper, dtype=np.float64), choices, np.asarray(defaults, dtype=np.float64))
