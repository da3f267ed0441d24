"""The residuals of a lens against a source lens, in pixels, over a grid of the image's pixel centres.

The source gives a ray ``d_s(x, y)`` at each pixel centre of the grid (the image's edges included).
Two residuals are offered, both in pixels:

- ``"direction"``: the candidate's ray ``d_c(x, y)`` at the same pixel, its difference from ``d_s``
  turned into a pixel offset through the candidate's local Jacobian, ``|J^+ (d_s - d_c)|`` with
  ``J = d d_c / d(x, y)``: smooth in the parameters and needing only forward maps;
- ``"pixel"``: where the candidate puts the source's ray, ``|p_c(d_s(x, y)) - (x, y)|``.

Pixels the candidate cannot map count as a residual of the image diagonal. :func:`lenslab.fit.fit_lens`
minimises their mean square (:class:`FitProblem`) and reports on a finer grid.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from lenslab.errors import FitError
from lenslab.fit.params import ParamSpace
from lenslab.lenses.core.base import Lens

FIT_GRID = 33  # samples along the longer side during the fit (plus the edge pixel centres)
REPORT_GRID = 257  # samples along the longer side for the final residual report


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
