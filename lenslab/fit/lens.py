"""Lens to lens: the parameters of one model that best reproduce another model's mapping.

The source lens and the candidate share the image size. Over a grid of pixel centres (the image's
edges included) the source gives a ray ``d_s(x, y)``. Two residuals are offered, both in pixels:

- ``space="direction"`` (default): the candidate's ray ``d_c(x, y)`` at the same pixel, its difference
  from ``d_s`` turned into a pixel offset through the candidate's local Jacobian,
  ``|J^+ (d_s - d_c)|`` with ``J = d d_c / d(x, y)``: the first-order form of the pixel residual below,
  smooth in the parameters and needing only forward maps;
- ``space="pixel"``: where the candidate puts the source's ray, ``|p_c(d_s(x, y)) - (x, y)|`` (uses the
  candidate's inverse, numerical for some models); the direction-space answer is its starting point.

The objective is the mean squared residual; pixels the candidate cannot map count as a residual of
the image diagonal. The report measures the fitted lens on a finer grid of pixel centres in pixel
space (the direction-space estimate for rays the fitted lens cannot place): RMS and maximum residual
and where the maximum is, how many source rays the fitted model does not see, and a verdict against
a tolerance. A poor fit is reported as such, never raised.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Mapping, Sequence

import numpy as np

from lenslab.errors import FitError
from lenslab.fit.digits import SHARE, fitted_text
from lenslab.fit.optimize import OptimizeResult, minimize
from lenslab.fit.params import ParamSpace, build_space
from lenslab.fit.problem import (FIT_GRID, REPORT_GRID, FitProblem, Residuals, can_see,  # noqa: F401
                                  pixel_grid, pixel_offset, project)
from lenslab.lenses import make_lens
from lenslab.lenses.core.base import Lens

DEFAULT_TOLERANCE = 0.5  # px: a fit whose maximum residual is below half a pixel is as good as exact


@dataclass
class LensFit:
    """The fitted lens and how well it reproduces the source."""

    source: Lens
    lens: Lens | None
    free: tuple[str, ...]
    residuals: Residuals | None
    optimizer: OptimizeResult | None
    space: str
    tolerance: float
    tried: list[tuple[str, float]] = field(default_factory=list)  # (spec, rms px) per choice combination
    seconds: float = 0.0
    bounds: tuple[np.ndarray, np.ndarray] | None = None

    @property
    def rms(self) -> float:
        return self.residuals.rms if self.residuals is not None else float("inf")

    @property
    def max(self) -> float:
        return self.residuals.max if self.residuals is not None else float("inf")

    @property
    def max_at(self) -> tuple[float, float]:
        return self.residuals.max_at if self.residuals is not None else (float("nan"), float("nan"))

    @property
    def unseen_fraction(self) -> float:
        return float(self.residuals.unseen.mean()) if self.residuals is not None else 1.0

    @property
    def unmapped_fraction(self) -> float:
        return float(1.0 - self.residuals.mapped.mean()) if self.residuals is not None else 1.0

    @property
    def ok(self) -> bool:
        return (self.lens is not None and self.optimizer is not None and self.optimizer.converged
                and self.unmapped_fraction == 0.0 and self.unseen_fraction == 0.0 and self.max <= self.tolerance)

    def at_bounds(self) -> list[str]:
        """Fitted parameters that ended on (within 1e-4 of the range of) a bound."""
        if self.optimizer is None or self.bounds is None:
            return []
        lo, hi = self.bounds
        out = []
        for name, x, a, b in zip(self.free, self.optimizer.x, lo, hi):
            tol = 1e-4 * (b - a)
            if x <= a + tol:
                out.append(f"{name} (at its lower bound {a:.6g})")
            elif x >= b - tol:
                out.append(f"{name} (at its upper bound {b:.6g})")
        return out

    def reason(self) -> str:
        """Why the fit is not good enough (empty when it is)."""
        if self.ok:
            return ""
        model = self.lens.name if self.lens is not None else "the model"
        if self.lens is None:
            return f"no parameter values make a valid {model} lens"
        parts = []
        if self.unseen_fraction > 0:
            d = self.source.pixel_to_dir(self.residuals.xy)[0][self.residuals.unseen]
            worst = float(np.degrees(np.arccos(np.clip(d[:, 2], -1, 1))).max())
            parts.append(f"the fitted {model} does not see {100 * self.unseen_fraction:.1f}% of the source's rays "
                         f"(some are {worst:.1f} deg from the axis)")
        pinned = self.at_bounds()
        if pinned:
            parts.append("the fit stopped against the bounds of " + ", ".join(pinned)
                         + ": the model needs values beyond them (or cannot represent the source)")
        if self.unmapped_fraction > 0 and self.unseen_fraction == 0:
            parts.append(f"{100 * self.unmapped_fraction:.1f}% of the samples fall outside what the fitted "
                         f"{model} maps")
        if self.max > self.tolerance:
            x, y = self.max_at
            parts.append(f"the residual reaches {self.max:.4g} px at ({x:.1f}, {y:.1f}), above the "
                         f"tolerance of {self.tolerance:g} px")
        if self.optimizer is not None and not self.optimizer.converged:
            parts.append("the optimiser did not converge")
        return "; ".join(parts) + ": try another model, free more parameters, or widen the bounds"

    def printed_spec(self) -> str:
        """The fitted spec with the digits the fit determines (:func:`lenslab.fit.digits.fitted_text`): pasted
        back, it moves no pixel by more than a tenth of the tolerance."""
        return fitted_text(self.lens, SHARE * self.tolerance)[0]

    def report(self) -> list[str]:
        lines = [f"source:   {self.source.spec()} at {self.source.width}x{self.source.height}"]
        if self.lens is not None:
            lines.append(f"fitted:   {self.printed_spec()}")
        lines.append(f"free:     {', '.join(self.free) or 'none'}")
        x, y = self.max_at
        lines.append(f"residual: RMS {self.rms:.4g} px, max {self.max:.4g} px at pixel ({x:.1f}, {y:.1f}) "
                     f"[{len(self.residuals.xy) if self.residuals else 0} pixel centres; fit in {self.space} space]")
        if self.residuals is not None and (self.unseen_fraction or self.unmapped_fraction):
            lines.append(f"coverage: {100 * (1 - self.unmapped_fraction):.1f}% of the source's pixels mapped, "
                         f"{100 * self.unseen_fraction:.1f}% of its rays out of the model's view")
        if len(self.tried) > 1:
            lines.append("tried:    " + "; ".join(f"{s} -> RMS {r:.4g} px" for s, r in self.tried))
        if self.optimizer is not None:
            lines.append(f"nlopt:    {self.optimizer.describe()}")
        lines.append(f"time:     {self.seconds:.2f} s")
        lines.append("verdict:  " + ("OK (max residual within "
                                     f"{self.tolerance:g} px)" if self.ok else "NOT A GOOD FIT: " + self.reason()))
        return lines


def fit_lens(
    source: Lens | str,
    model: str,
    *,
    size: tuple[int, int] | None = None,
    free: Sequence[str] | str | None = None,
    bounds: Mapping[str, tuple[float, float]] | str | None = None,
    space: str = "direction",
    method: str = "bobyqa",
    global_start: str | None = "auto",
    tolerance: float = DEFAULT_TOLERANCE,
    grid: int = FIT_GRID,
    report_grid: int = REPORT_GRID,
    start: Mapping[str, float] | None = None,
    first_space: str = "direction",
) -> LensFit:
    """Fit the model spec ``model`` to the ``source`` lens over its whole image.

    Never raises for a poor fit: the result says how good it is (``ok``, ``reason()``).

    Parameters
    ----------
    source : Lens or str
        The lens to reproduce, or its spec (then ``size`` is needed).
    model : str
        The model to fit, as a spec; the values it gives are start values (fitted) or fixed values.
    size : tuple of int, optional
        (W, H) of the image, when ``source`` is a spec or should be taken at another size.
    free : str or sequence of str, optional
        The parameters to fit (``"fov"``, ``"fx,fy,k1"``); by default the model's own choice.
    bounds : mapping or str, optional
        Search ranges, ``{"fov": (90, 200)}`` or ``"fov=90:200"``; by default the model's ranges.
    space : str
        The residual measured: ``"direction"`` (the rays' difference as a pixel offset) or ``"pixel"``
        (where the fitted lens puts the source's ray), both in pixels.
    method : str
        The nlopt local method: ``"bobyqa"``, ``"sbplx"`` or ``"cobyla"``.
    global_start : str, optional
        None (local search from the start values), ``"direct-l"`` or ``"mlsl"`` (global search first),
        or ``"auto"`` (local first; a DIRECT-L global start as well when that is not within ``tolerance``).
    tolerance : float
        The largest residual, in pixels, that counts as a good fit.
    grid : int
        Samples along the longer side of the image during the fit (plus the edge pixel centres).
    report_grid : int
        Samples along the longer side for the final residual report.
    start : mapping, optional
        Start values (fitted) or values (fixed) the spec does not give.
    first_space : str
        ``"pixel"`` fits in pixel space from the start (no direction-space stage).

    Returns
    -------
    LensFit
        The fitted ``lens``, its ``rms`` and ``max`` residual in pixels (and ``max_at``), the share of
        the source's rays it does not see, ``ok`` and ``reason()``.

    Raises
    ------
    lenslab.errors.FitError
        An unknown residual space or parameter name, or a spec without a size.

    Examples
    --------
    A 90-degree pinhole, 64 pixels wide, is OpenCV's model with ``fx = 32 / tan(45 deg) = 32``:

    >>> from lenslab.fit import fit_lens
    >>> fit = fit_lens("perspective:fov=90", "opencv:fx=40,fy=40", size=(64, 48), free="fx,fy",
    ...                global_start=None, report_grid=33)
    >>> round(fit.lens.fx, 6), round(fit.lens.fy, 6), fit.ok, fit.max < 1e-6
    (32.0, 32.0, True, True)
    """
    import time

    t_start = time.perf_counter()
    if space not in ("direction", "pixel"):
        raise FitError(f"unknown residual space {space!r}; choose direction or pixel")
    if isinstance(source, str):
        if size is None:
            raise FitError("an image size is needed to fit against a lens spec; give size=(W, H)")
        source = make_lens(source, size)
    elif size is not None and tuple(size) != (source.width, source.height):
        source = source.with_size(*size)
    ps = build_space(model, (source.width, source.height), free=free, bounds=bounds, start_from=source,
                     start_values=start)
    problem = FitProblem(source, grid, first_space)
    polish = FitProblem(source, grid, "pixel") if space == "pixel" and first_space != "pixel" else None
    starts = [ps.start] + ([ps.defaults] if not np.array_equal(ps.defaults, ps.start) else [])
    best: tuple[float, Any, OptimizeResult | None] = (float("inf"), None, None)
    tried: list[tuple[str, float]] = []
    for combo in ps.combinations():
        res = _search(problem.objective(ps, combo), ps, starts, method, global_start, tolerance)
        if res is None:
            continue
        if polish is not None:  # the direction-space answer starts the pixel-space fit
            f = polish.objective(ps, combo)
            refined = _attempt(f, ps, res.x, method, None)
            stages = res.stages + [s for s in refined.stages]
            if refined.value > f(res.x):  # pragma: no cover - a local search never ends above its start
                refined = res
                refined.value = f(res.x)
            refined.stages, refined.evaluations = stages, res.evaluations + refined.evaluations
            res = refined
        lens = ps.try_make(res.x, combo)
        tried.append((fitted_text(lens, SHARE * tolerance)[0] if lens is not None else f"{ps.model} {combo}", float(np.sqrt(res.value))))
        if res.value < best[0]:
            best = (res.value, combo, res)
    _, combo, res = best
    if res is None:
        return LensFit(source, None, ps.names, None, None, space, tolerance, tried, time.perf_counter() - t_start)
    lens = ps.try_make(res.x, combo)
    report = FitProblem(source, report_grid, space).report(lens)
    return LensFit(source, lens, ps.names, report, res, space, tolerance, tried, time.perf_counter() - t_start,
                   (ps.lower, ps.upper))


#: what the starts of :func:`_search` are, in order (the source's own values, then the model's defaults)
START_NAMES = ("the source's values", "the model's defaults")


def _search(f, ps: ParamSpace, starts, method: str, global_start: str | None, tolerance: float):
    """Local searches from each start; a global start as asked (or, for "auto", when they fall short)."""
    candidates = []
    if global_start in (None, "auto") or not ps.names:
        candidates += [_attempt(f, ps, s0, method, None) for s0 in starts]
        if len(starts) > 1:  # say which start each local search began from: their bests differ
            for c, where in zip(candidates, START_NAMES):
                for stage in c.stages:
                    stage.algorithm = f"{stage.algorithm} from {where}"
    if global_start is not None and ps.names:  # (nothing free: the one evaluation is the answer)
        ok_local = any(c.value <= _tol_value(tolerance) for c in candidates)
        if global_start != "auto" or not ok_local:
            candidates.append(_attempt(f, ps, starts[0], method, "direct-l" if global_start == "auto" else global_start))
    if not candidates:
        return None
    res = min(candidates, key=lambda c: c.value)
    if len(candidates) > 1:  # keep the record of every search
        res.stages = [s for c in candidates for s in c.stages]
        res.evaluations = sum(c.evaluations for c in candidates)
    return res


def _tol_value(tolerance: float) -> float:
    # mean squared residual small enough that the local answer is taken without a global search
    return (0.25 * tolerance) ** 2


def _attempt(f, ps: ParamSpace, start, method: str, global_start: str | None) -> OptimizeResult:
    try:
        return minimize(f, start, ps.lower, ps.upper, names=ps.names, method=method, global_start=global_start,
                        stopval=1e-30)
    except FitError as exc:
        if exc.best is not None:
            return exc.best  # its ``converged`` is False: the report says so
        raise
