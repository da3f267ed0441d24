"""Model to model: a camera of one model re-expressed in another, fitted over the field both share.

``convert_lens(source, "kannala-brandt")`` fits the target model so that, for every pixel centre of
the source whose ray the target sees inside its image, the target puts that ray on the same pixel.
Its start follows the source (:func:`lenslab.fit.start.source_start`): the same image size, the source's principal point
(the pixel that sees the optical axis) and a focal length from the source's central scale (pixels per
radian next to the axis), made the target's by the target's own central scale. The fit is nlopt's
BOBYQA in pixel space from there, through :func:`lenslab.fit.lens.fit_lens`; the report is RMS and
maximum residual in pixels over the shared field, where the maximum lies, and a residual map.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from lenslab.errors import FitError, FitSpecError
from lenslab.lenses.core.base import Lens
from lenslab.fit.digits import SHARE, fitted_text
from lenslab.fit.start import source_start

#: the aim of a conversion: RMS residual over the shared field, px
DEFAULT_AIM = 0.05


@dataclass
class Conversion:
    fit: object  # lenslab.fit.lens.LensFit
    aim: float
    shared: float  # share of the source's pixel centres in the shared field
    grid: np.ndarray  # (m, 2) the report's pixel centres
    residual: np.ndarray  # (m,) px, NaN outside the shared field

    @property
    def lens(self):
        return self.fit.lens

    @property
    def rms(self) -> float:
        r = self.residual[np.isfinite(self.residual)]
        return float(np.sqrt(np.mean(r * r))) if r.size else float("inf")

    @property
    def max(self) -> float:
        r = self.residual[np.isfinite(self.residual)]
        return float(r.max()) if r.size else float("inf")

    @property
    def max_at(self) -> tuple[float, float]:
        if not np.isfinite(self.residual).any():
            return (float("nan"), float("nan"))
        i = int(np.nanargmax(self.residual))
        return float(self.grid[i, 0]), float(self.grid[i, 1])

    @property
    def met(self) -> bool:
        return self.fit.lens is not None and self.rms < self.aim

    def residual_map(self, cells: int = 8) -> list[str]:
        """The largest residual in each of ``cells`` x ``cells`` parts of the image, as text rows."""
        w, h = self.fit.source.width, self.fit.source.height
        cx = np.minimum((self.grid[:, 0] / w * cells).astype(int), cells - 1)
        cy = np.minimum((self.grid[:, 1] / h * cells).astype(int), cells - 1)
        rows = []
        for j in range(cells):
            row = []
            for i in range(cells):
                r = self.residual[(cx == i) & (cy == j)]
                r = r[np.isfinite(r)]
                row.append(f"{r.max():8.3g}" if r.size else "       -")
            rows.append(" ".join(row))
        return rows

    def image(self, size: tuple[int, int]) -> np.ndarray:
        """The residual (px) at every pixel centre of the report grid, spread to a float32 image (NaN:
        not shared)."""
        w, h = size
        img = np.full((h, w, 1), np.nan, dtype=np.float32)
        xi = np.floor(self.grid[:, 0]).astype(int)
        yi = np.floor(self.grid[:, 1]).astype(int)
        img[yi, xi, 0] = self.residual
        return img

    def report(self) -> list[str]:
        f = self.fit
        lines = [f"source:   {f.source.spec()} ({f.source.width}x{f.source.height})"]
        if f.lens is not None:
            lines.append(f"target:   {fitted_text(f.lens, SHARE * self.aim)[0]}")
        lines.append(f"free:     {', '.join(f.free) or 'none'}")
        lines.append(f"field:    {100 * self.shared:.2f}% of the source's pixel centres shared "
                     f"({len(self.grid)} sampled)")
        if f.lens is not None:
            x, y = self.max_at
            lines.append(f"residual: RMS {self.rms:.3g} px, max {self.max:.3g} px at pixel ({x:.1f}, {y:.1f}), "
                         f"{self.where(x, y)}")
        if f.optimizer is not None:
            lines.append(f"nlopt:    {f.optimizer.describe()}")
        verdict = "met" if self.met else "MISSED"
        lines.append(f"aim:      RMS below {self.aim:g} px over the shared field: {verdict}")
        if not self.met:
            lines.append("why:      " + (self.why()))
            lines.append("residual map (max px per eighth of the image, top row first):")
            lines += ["  " + r for r in self.residual_map()]
        return lines

    def where(self, x: float, y: float) -> str:
        """Where a pixel lies in the source's field: its angle from the axis and its direction."""
        d, ok = self.fit.source.pixel_to_dir(np.array([[x, y]]))
        if not ok[0]:
            return "outside the source's field"
        angle = float(np.degrees(np.arccos(np.clip(d[0, 2], -1.0, 1.0))))
        w, h = self.fit.source.width, self.fit.source.height
        edge = min(x, y, w - x, h - y)
        place = "in a corner" if edge < 0.05 * min(w, h) and min(abs(x - w / 2), abs(y - h / 2)) > 0.3 * min(w, h) \
            else "at the edge" if edge < 0.05 * min(w, h) else "inside the image"
        return f"{angle:.1f} deg from the axis, {place}"

    def why(self) -> str:
        f = self.fit
        if f.lens is None:
            return "no parameter values make a valid lens of the target model"
        parts = [f"the {f.lens.name} model reproduces the source to RMS {self.rms:.3g} px, not below {self.aim:g}"]
        if f.optimizer is not None and not f.optimizer.converged:
            parts.append("the optimiser did not converge")
        pinned = f.at_bounds()
        if pinned:
            parts.append("the fit stopped against the bounds of " + ", ".join(pinned))
        if self.shared < 1.0:
            parts.append(f"{100 * (1 - self.shared):.1f}% of the source's field is outside the target's")
        return "; ".join(parts) + ": free more parameters (--free), try another model, or accept the fit with --aim"


def convert_lens(source: Lens, model: str, *, free=None, bounds=None, aim: float = DEFAULT_AIM) -> Conversion:
    """Fit the model spec ``model`` to ``source`` over the field both share (see the module's text)."""
    from lenslab.fit.lens import fit_lens
    from lenslab.fit.params import EXTRA_TERMS, NOT_FITTED_BY_DEFAULT
    from lenslab.lenses import REGISTRY, parse_spec

    name, given = parse_spec(model)
    if name not in REGISTRY:
        raise FitSpecError(f"unknown lens model {name!r}; valid models: {', '.join(sorted(REGISTRY))}")
    cls = REGISTRY[name]
    spec = dict(given)
    if {"width", "height"} <= {p.name for p in cls.params}:
        spec.setdefault("width", source.width)
        spec.setdefault("height", source.height)
    if free is None:
        extras = set(EXTRA_TERMS.get(name, ())) - set(given)
        spec.update({k: 0.0 for k in extras})
        skip = (NOT_FITTED_BY_DEFAULT - {"cx", "cy"}) | extras | set(given)  # a conversion moves the centre too
        free = [p.name for p in cls.params if p.kind is float and p.name not in skip]
    text = name + ":" + ",".join(f"{k}={v!r}" if isinstance(v, float) else f"{k}={v}" for k, v in spec.items()) \
        if spec else name
    fit = fit_lens(source, text, free=free, bounds=bounds, space="pixel", global_start="auto",
                   tolerance=float("inf"), start=source_start(cls, source, given), first_space="pixel")
    grid, residual, shared = shared_residuals(fit)
    return Conversion(fit, aim, shared, grid, residual)


def shared_residuals(fit) -> tuple[np.ndarray, np.ndarray, float]:
    """The report's pixel centres, the pixel residual there (NaN outside the shared field: where the
    target does not put the source's ray inside its image) and the share of the field shared."""
    from lenslab.fit.lens import REPORT_GRID, FitProblem

    problem = FitProblem(fit.source, REPORT_GRID, "pixel")
    if fit.lens is None:
        return problem.xy, np.full(len(problem.xy), np.nan), 0.0
    r, ok = problem.pixel_residual(fit.lens)
    return problem.xy, np.where(ok, r, np.nan), float(ok.mean())
