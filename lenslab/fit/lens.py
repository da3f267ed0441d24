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
from typing import Any, Sequence

import numpy as np

from lenslab.errors import FitError
from lenslab.fit.optimize import OptimizeResult, minimize
from lenslab.fit.params import ParamSpace, build_space
from lenslab.lenses import make_lens
from lenslab.lenses.core.base import Lens

FIT_GRID = 33  # samples along the longer side during the fit (plus the edge pixel centres)
REPORT_GRID = 257  # samples along the longer side for the final residual report
DEFAULT_TOLERANCE = 0.5  # px: a fit whose maximum residual is below half a pixel is as good as exact


def pixel_grid(size: tuple[int, int], n: int) -> np.ndarray:
    """Pixel centres on a grid of about ``n`` samples along the longer side, edges included: (m, 2)."""
    w, h = size
    nx = max(2, min(w, int(round(n * w / max(w, h)))))
    ny = max(2, min(h, int(round(n * h / max(w, h)))))
    xs = np.unique(np.round(np.linspace(0, w - 1, nx))) + 0.5
    ys = np.unique(np.round(np.linspace(0, h - 1, ny))) + 0.5
    gx, gy = np.meshgrid(xs, ys)
    return np.stack([gx.ravel(), gy.ravel()], axis=-1).astype(np.float64)


def pixel_offset(lens: Lens, xy: np.ndarray, d_at: np.ndarray, d_target: np.ndarray) -> np.ndarray:
    """First-order pixel offset that turns the lens's ray ``d_at`` at ``xy`` into ``d_target``: (m,) px.

    ``J = d dir / d(x, y)`` by one-sided differences of an eighth of a pixel (backward where the forward
    neighbour is invalid); the offset is the least-squares solution of ``J delta = d_target - d_at``.
    Infinite where the Jacobian is degenerate.
    """
    h = 0.125
    cols = []
    for axis in (0, 1):
        step = np.zeros(2)
        step[axis] = h
        dp, vp = lens.pixel_to_dir(xy + step)
        dm, _ = lens.pixel_to_dir(xy - step)
        cols.append(np.where(vp[:, None], dp - d_at, d_at - dm) / h)
    jx, jy = cols
    a = np.einsum("mi,mi->m", jx, jx)
    b = np.einsum("mi,mi->m", jx, jy)
    c = np.einsum("mi,mi->m", jy, jy)
    det = a * c - b * b
    delta = d_target - d_at
    px, py = np.einsum("mi,mi->m", jx, delta), np.einsum("mi,mi->m", jy, delta)
    with np.errstate(all="ignore"):
        ox = (c * px - b * py) / det
        oy = (a * py - b * px) / det
        r = np.hypot(ox, oy)
    return np.where(det > 1e-30 * (a * c + 1e-300), r, np.inf)


def project(lens: Lens, d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Pixel positions of directions, not clipped to the image where the model allows (its uv map).

    A candidate lens that puts a ray half a pixel beyond the border still gets a residual, so the
    objective stays continuous at the image's edges.
    """
    try:
        with np.errstate(all="ignore"):
            uv, valid = lens.dir_to_uv(d)
            xy = lens.uv_to_pixel(uv)
        valid = np.asarray(valid, dtype=bool) & np.all(np.isfinite(xy), axis=-1)
        return np.where(valid[..., None], xy, 0.0), valid
    except NotImplementedError:
        return lens.dir_to_pixel(d)


def can_see(lens: Lens, d: np.ndarray) -> np.ndarray:
    """Whether the lens model maps the direction anywhere (ignoring the image's borders where it can)."""
    try:
        with np.errstate(all="ignore"):
            _, valid = lens.dir_to_uv(d)
        return np.asarray(valid, dtype=bool)
    except NotImplementedError:
        return lens.dir_to_pixel(d)[1]


@dataclass
class Residuals:
    """Per-sample residuals of a candidate lens against the source (pixels)."""

    xy: np.ndarray  # (m, 2) sample positions
    r: np.ndarray  # (m,) residual in px (penalty where not mapped)
    mapped: np.ndarray  # (m,) the candidate gives a residual there
    unseen: np.ndarray  # (m,) source rays the candidate's model cannot see at all

    @property
    def rms(self) -> float:
        return float(np.sqrt(np.mean(self.r[self.mapped] ** 2))) if self.mapped.any() else float("inf")

    @property
    def max(self) -> float:
        return float(self.r[self.mapped].max()) if self.mapped.any() else float("inf")

    @property
    def max_at(self) -> tuple[float, float]:
        if not self.mapped.any():
            return (float("nan"), float("nan"))
        i = np.flatnonzero(self.mapped)[np.argmax(self.r[self.mapped])]
        return float(self.xy[i, 0]), float(self.xy[i, 1])


class FitProblem:
    """Source samples prepared once; residuals of any candidate lens against them."""

    def __init__(self, source: Lens, n: int, space: str):
        self.source, self.space = source, space
        xy = pixel_grid((source.width, source.height), n)
        d, valid = source.pixel_to_dir(xy)
        if not valid.any():
            raise FitError(f"the source lens {source.spec()} has no valid pixel to fit against")
        self.xy, self.d = xy[valid], d[valid]
        self.penalty = float(np.hypot(source.width, source.height))

    def direction_residual(self, lens: Lens) -> tuple[np.ndarray, np.ndarray]:
        dc, ok = lens.pixel_to_dir(self.xy)
        r = pixel_offset(lens, self.xy, dc, self.d)
        # beyond a quarter turn the linearisation says nothing: count at least the full penalty
        far = np.einsum("mi,mi->m", dc, self.d) < 0
        r = np.where(far, np.maximum(r, self.penalty), r)
        return r, ok & np.isfinite(r)

    def pixel_residual(self, lens: Lens) -> tuple[np.ndarray, np.ndarray]:
        p, ok = project(lens, self.d)
        r = np.hypot(p[:, 0] - self.xy[:, 0], p[:, 1] - self.xy[:, 1])
        return r, ok & np.isfinite(r)

    def _none(self) -> Residuals:
        m = len(self.xy)
        none = np.zeros(m, dtype=bool)
        return Residuals(self.xy, np.full(m, self.penalty), none, ~none)

    def residuals(self, lens: Lens | None) -> Residuals:
        """The fit's residuals, in its space; the image diagonal where the candidate maps nothing."""
        if lens is None:
            return self._none()
        if self.space == "pixel":  # where the inverse fails, the direction-space estimate keeps a slope
            return self.report(lens)
        r, ok = self.direction_residual(lens)
        r = np.where(ok, r, self.penalty)
        return Residuals(self.xy, r, ok, ~can_see(lens, self.d))

    def report(self, lens: Lens | None) -> Residuals:
        """Residuals for the report: in pixel space where the lens sees the source's ray, else the
        direction-space estimate (so rays the lens cannot place still show how far off they are)."""
        if lens is None:
            return self._none()
        rp, okp = self.pixel_residual(lens)
        seen = can_see(lens, self.d)
        if okp.all():
            return Residuals(self.xy, rp, okp, ~seen)
        rd, okd = self.direction_residual(lens)
        r = np.where(okp, rp, np.where(okd, rd, self.penalty))
        return Residuals(self.xy, r, okp | okd, ~seen)

    def objective(self, space: ParamSpace, combo) -> Any:
        def f(x: np.ndarray) -> float:
            res = self.residuals(space.try_make(x, combo))
            return float(np.mean(res.r ** 2))
        return f


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

    def report(self) -> list[str]:
        lines = [f"source:   {self.source.spec()} at {self.source.width}x{self.source.height}"]
        if self.lens is not None:
            lines.append(f"fitted:   {self.lens.spec()}")
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
    bounds=None,
    space: str = "direction",
    method: str = "bobyqa",
    global_start: str | None = "auto",
    tolerance: float = DEFAULT_TOLERANCE,
    grid: int = FIT_GRID,
    report_grid: int = REPORT_GRID,
    start: dict | None = None,
    first_space: str = "direction",
) -> LensFit:
    """Fit the model spec ``model`` to the ``source`` lens over its whole image.

    ``global_start``: ``None`` (local search from the start values), ``"direct-l"`` or ``"mlsl"`` (global
    search first), or ``"auto"`` (local first; a DIRECT-L global start as well when that is not within
    ``tolerance``). ``start`` overrides start values (fitted) or values (fixed) the spec does not give;
    ``first_space="pixel"`` fits in pixel space from the start (no direction-space stage). Never raises
    for a poor fit: the result says how good it is (``ok``, ``reason()``).
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
        tried.append((lens.spec() if lens is not None else f"{ps.model} {combo}", float(np.sqrt(res.value))))
        if res.value < best[0]:
            best = (res.value, combo, res)
    _, combo, res = best
    if res is None:
        return LensFit(source, None, ps.names, None, None, space, tolerance, tried, time.perf_counter() - t_start)
    lens = ps.try_make(res.x, combo)
    report = FitProblem(source, report_grid, space).report(lens)
    return LensFit(source, lens, ps.names, report, res, space, tolerance, tried, time.perf_counter() - t_start,
                   (ps.lower, ps.upper))


def _search(f, ps: ParamSpace, starts, method: str, global_start: str | None, tolerance: float):
    """Local searches from each start; a global start as asked (or, for "auto", when they fall short)."""
    candidates = []
    if global_start in (None, "auto") or not ps.names:
        candidates += [_attempt(f, ps, s0, method, None) for s0 in starts]
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
