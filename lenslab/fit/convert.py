"""Model to model: a camera of one model re-expressed in another, fitted over the field both share.

``convert_lens(source, "kannala-brandt")`` fits the target model so that, for every pixel centre of
the source whose ray the target sees inside its image, the target puts that ray on the same pixel.
Its start follows the source (:func:`source_start`): the same image size, the source's principal point
(the pixel that sees the optical axis) and a focal length from the source's central scale (pixels per
radian next to the axis), made the target's by the target's own central scale. The fit is nlopt's
BOBYQA in pixel space from there, through :func:`lenslab.fit.lens.fit_lens`; the report is RMS and
maximum residual in pixels over the shared field, where the maximum lies, and a residual map.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from lenslab.errors import FitError, LensError
from lenslab.lenses.base import Lens

#: the aim of a conversion: RMS residual over the shared field, px
DEFAULT_AIM = 0.05
CENTRAL_STEP = 0.25  # px either side of the principal point for the central scale


def principal_point(lens: Lens) -> tuple[float, float]:
    """The lenslab pixel that sees the optical axis (the image centre where the lens does not see it)."""
    xy, ok = lens.dir_to_pixel(np.array([0.0, 0.0, 1.0]))
    if ok:
        return float(xy[0]), float(xy[1])
    return lens.width / 2.0, lens.height / 2.0


def central_scale(lens: Lens, at: tuple[float, float] | None = None) -> tuple[float, float]:
    """Pixels per radian along x and y at the principal point (central differences of the rays)."""
    x, y = principal_point(lens) if at is None else at
    h = CENTRAL_STEP
    pts = np.array([[x - h, y], [x + h, y], [x, y - h], [x, y + h]])
    d, ok = lens.pixel_to_dir(pts)
    if not ok.all():
        raise FitError(f"{lens.spec()}: no ray next to its principal point ({x:.2f}, {y:.2f}); cannot scale a "
                       "focal length from it")
    ax = 2.0 * np.arcsin(np.linalg.norm(d[1] - d[0]) / 2.0)
    ay = 2.0 * np.arcsin(np.linalg.norm(d[3] - d[2]) / 2.0)
    return 2.0 * h / ax, 2.0 * h / ay


def source_start(target_cls: type, source: Lens, given: dict) -> dict[str, float]:
    """Start values of a calibrated target's intrinsics that follow the source (those not ``given``):
    its principal point (OpenCV's numbers: lenslab's pixel minus 0.5) and focal lengths that give the
    target the source's central scale, with the target's other parameters at ``given`` or default."""
    names = getattr(target_cls, "intrinsic_names", ())
    if not {"fx", "fy", "cx", "cy"} <= set(names):
        return {}
    w, h = source.width, source.height
    px, py = principal_point(source)
    out = {"cx": px - 0.5, "cy": py - 0.5}
    sx, sy = central_scale(source, (px, py))
    probe = {p.name: p.default for p in target_cls.params if p.kind is float}
    probe.update({k: v for k, v in given.items() if k in probe})
    f0 = 0.25 * max(w, h)
    probe.update(fx=f0, fy=f0, cx=px - 0.5, cy=py - 0.5, width=w, height=h)
    try:
        tx, ty = central_scale(target_cls(w, h, **probe), (px, py))
    except (LensError, FitError):  # the target's own values leave no ray at the centre: keep its default
        tx = ty = None
    if tx is not None:
        out["fx"], out["fy"] = f0 * sx / tx, f0 * sy / ty
    gw, gh = int(given.get("width") or w), int(given.get("height") or h)
    if (gw, gh) != (w, h):  # the spec's calibration image is another size: its pixels
        out.update(target_cls.scale({**{k: probe[k] for k in ("fx", "fy", "cx", "cy")}, **out}, gw / w, gh / h))
    return {k: v for k, v in out.items() if k not in given}


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
            lines.append(f"target:   {f.lens.spec()}")
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
        d, ok = self.fit.source.pixel_to_dir(np.array([x, y]))
        if not ok:
            return "outside the source's field"
        angle = float(np.degrees(np.arccos(np.clip(d[2], -1.0, 1.0))))
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
        raise FitError(f"unknown lens model {name!r}; valid models: {', '.join(sorted(REGISTRY))}")
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
    from lenslab.fit.lens import REPORT_GRID, _Problem

    problem = _Problem(fit.source, REPORT_GRID, "pixel")
    if fit.lens is None:
        return problem.xy, np.full(len(problem.xy), np.nan), 0.0
    r, ok = problem.pixel_residual(fit.lens)
    return problem.xy, np.where(ok, r, np.nan), float(ok.mean())
