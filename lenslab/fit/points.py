"""Calibration from measured points: a lens (and optionally its orientation) from pixel <-> direction pairs.

Input is a list of pixels ``(x, y)`` in the unknown camera's image with the direction each one sees,
either given (``dx, dy, dz`` or ``lon, lat`` in degrees) or taken from the same feature's pixel in a
known source camera. The residual of a point is its reprojection error in pixels,
``|p(d_i) - (x_i, y_i)|``. Measured points contain mistakes, so the fit runs in two passes:

1. minimise the robust cost ``s^2 * sum(rho((r_i / s)^2))`` with the loss ``rho`` (``cauchy`` by default;
   also ``huber``, ``soft_l1``, ``arctan``, ``linear``) and scale ``s`` in pixels, which lets gross
   outliers pull with little or no force;
2. call a point an outlier when its residual exceeds ``outlier`` pixels (``3 s`` by default), and refit
   the inliers by plain least squares from there.

The result lists every point's residual and whether it was kept.
"""

from __future__ import annotations

import csv
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Mapping, Sequence

import numpy as np

from lenslab.errors import FitError
from lenslab.fit.digits import SHARE, fitted_text
from lenslab.fit.problem import project
from lenslab.fit.optimize import OptimizeResult, minimize
from lenslab.fit.params import ParamSpace, build_space
from lenslab.lenses import Camera, Pose
from lenslab.lenses.core.base import Lens, normalize

LOSSES = {
    "linear": lambda s: s,
    "huber": lambda s: np.where(s <= 1.0, s, 2.0 * np.sqrt(s) - 1.0),
    "soft_l1": lambda s: 2.0 * (np.sqrt(1.0 + s) - 1.0),
    "cauchy": np.log1p,
    "arctan": np.arctan,
}
POSE_NAMES = ("yaw", "pitch", "roll")
POSE_BOUNDS = ((-180.0, 180.0), (-90.0, 90.0), (-180.0, 180.0))


# -- reading the CSV ------------------------------------------------------------------------------
@dataclass
class PointSet:
    """Measured points: pixels in the unknown camera and the (world) direction each one sees."""

    xy: np.ndarray  # (n, 2) float64
    dirs: np.ndarray  # (n, 3) float64, unit
    labels: list[str]  # "line N" of the CSV, for the per-point report


def _floats(row: list[str], line: int, path) -> list[float]:
    try:
        return [float(v) for v in row]
    except ValueError:
        raise FitError(f"{path}, line {line}: expected numbers, got {','.join(row)!r}") from None


def lonlat_to_dir(lon_deg: np.ndarray, lat_deg: np.ndarray) -> np.ndarray:
    """Longitude (0 forward +z, positive toward +x) and latitude (up +y) in degrees -> unit vectors."""
    lon, lat = np.radians(lon_deg), np.radians(lat_deg)
    return np.stack([np.cos(lat) * np.sin(lon), np.sin(lat), np.cos(lat) * np.cos(lon)], axis=-1)


def read_points(path: str | Path, source: Camera | None = None) -> PointSet:
    """Read a calibration CSV.

    Columns, by header name (a header row is needed when the file has four columns):

    - ``x, y, dx, dy, dz``: pixel and direction (need not be unit length);
    - ``x, y, lon, lat``: pixel and direction as longitude/latitude in degrees (lon 0 = forward);
    - ``src_x, src_y, x, y``: the same feature in a known ``source`` camera and in the unknown one.

    Blank lines and lines starting with ``#`` are skipped.

    Parameters
    ----------
    path : str or pathlib.Path
        The CSV file (a regular file of at most 64 MiB).
    source : lenslab.lenses.Camera, optional
        The known camera of ``src_x, src_y`` columns, which gives their directions.

    Returns
    -------
    PointSet
        Pixels ``xy`` (n x 2), unit directions ``dirs`` (n x 3, float64) and each point's line.

    Raises
    ------
    lenslab.errors.FitError
        No points, a cell that is not a number, rows of different lengths, unknown columns, or
        ``src_x, src_y`` columns without a ``source`` camera.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from lenslab.fit import read_points
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "points.csv"
    >>> _ = path.write_text("x,y,lon,lat\\n# the centre sees forward\\n32,32,0,0\\n64,32,90,0\\n")
    >>> points = read_points(path)
    >>> points.xy.tolist(), (points.dirs.round(12) + 0.0).tolist(), points.labels
    ([[32.0, 32.0], [64.0, 32.0]], [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0]], ['line 3', 'line 4'])
    """
    import io

    from lenslab.inputs.sidefile import read_side_text

    path = Path(path)
    text = read_side_text(path, "points file", 64 << 20)  # a regular file of bounded size
    rows = [(i + 1, [c.strip() for c in r]) for i, r in enumerate(csv.reader(io.StringIO(text, newline="")))
            if r and any(c.strip() for c in r) and not r[0].lstrip().startswith("#")]
    header = None
    try:
        float(rows[0][1][0]) if rows else None
    except ValueError:
        header = [h.lower() for h in rows[0][1]]
        rows = rows[1:]
    if not rows:
        raise FitError(f"{path}: no points; give one CSV row per point (x,y,dx,dy,dz)")
    data = [(line, _floats(r, line, path)) for line, r in rows]
    ncol = {len(r) for _, r in data}
    if len(ncol) != 1:
        raise FitError(f"{path}: rows have different numbers of columns ({sorted(ncol)}); fix the file")
    (ncol,) = ncol
    arr = np.asarray([r for _, r in data], dtype=np.float64)
    labels = [f"line {line}" for line, _ in data]
    if header is None:
        if ncol == 5:
            header = ["x", "y", "dx", "dy", "dz"]
        elif ncol == 4:
            header = ["src_x", "src_y", "x", "y"] if source is not None else ["x", "y", "lon", "lat"]
        else:
            raise FitError(f"{path}: {ncol} columns without a header; use x,y,dx,dy,dz or x,y,lon,lat or "
                           "src_x,src_y,x,y (with a header row naming them)")
    if len(header) != ncol:
        raise FitError(f"{path}: the header names {len(header)} columns but rows have {ncol}")
    col = {name: arr[:, i] for i, name in enumerate(header)}
    if "x" not in col or "y" not in col:
        raise FitError(f"{path}: no x and y columns (header: {', '.join(header)})")
    xy = np.stack([col["x"], col["y"]], axis=-1)
    if {"dx", "dy", "dz"} <= col.keys():
        d = np.stack([col["dx"], col["dy"], col["dz"]], axis=-1)
    elif {"lon", "lat"} <= col.keys():
        d = lonlat_to_dir(col["lon"], col["lat"])
    elif {"src_x", "src_y"} <= col.keys():
        if source is None:
            raise FitError(f"{path}: pixel pairs need the known source camera; give --source SPEC")
        _, d, ok = source.pixel_to_world(np.stack([col["src_x"], col["src_y"]], axis=-1))
        if not ok.all():
            bad = ", ".join(labels[i] for i in np.flatnonzero(~ok)[:5])
            raise FitError(f"{path}: source pixels outside the source lens's valid area ({bad}); fix or remove them")
    else:
        raise FitError(f"{path}: no direction columns: give dx,dy,dz or lon,lat or src_x,src_y")
    n = np.linalg.norm(d, axis=-1)
    if not (np.all(np.isfinite(xy)) and np.all(np.isfinite(d)) and np.all(n > 0)):
        raise FitError(f"{path}: every point needs a finite pixel and a non-zero direction")
    return PointSet(xy, normalize(d), labels)


# -- the fit --------------------------------------------------------------------------------------
@dataclass
class PointsFit:
    """The calibrated camera and every point's residual."""

    camera: Camera
    residuals: np.ndarray  # (n,) px; inf where the fitted camera cannot see the point's direction
    inlier: np.ndarray  # (n,) bool
    points: PointSet
    free: tuple[str, ...]
    loss: str
    scale: float
    threshold: float
    robust: OptimizeResult
    refit: OptimizeResult | None
    seconds: float = 0.0
    tried: list[tuple[str, float]] = field(default_factory=list)

    @property
    def lens(self) -> Lens:
        return self.camera.lens

    @property
    def rms(self) -> float:
        """RMS residual of the inliers (px)."""
        r = self.residuals[self.inlier]
        return float(np.sqrt(np.mean(r ** 2))) if r.size else float("inf")

    @property
    def max(self) -> float:
        r = self.residuals[self.inlier]
        return float(r.max()) if r.size else float("inf")

    @property
    def ok(self) -> bool:
        enough = self.inlier.sum() >= max(len(self.free) + 1, int(np.ceil(0.5 * len(self.inlier))))
        converged = self.robust.converged and (self.refit is None or self.refit.converged)
        return bool(enough and converged and np.isfinite(self.rms))

    def report(self, per_point: bool = True) -> list[str]:
        yaw, pitch, roll = self.camera.pose.ypr
        n, k = len(self.inlier), int(self.inlier.sum())
        posed = any(p in self.free for p in POSE_NAMES)
        spec, angles = fitted_text(self.lens, SHARE * self.scale, (yaw, pitch, roll) if posed else None)
        lines = [f"fitted:   {spec} at {self.lens.width}x{self.lens.height}"]
        if posed:
            lines.append("pose:     yaw={0} pitch={1} roll={2} (as options: --yaw {0} --pitch {1} --roll {2})".format(*angles))
        lines.append(f"free:     {', '.join(self.free)}")
        lines.append(f"points:   {n}, inliers {k}, outliers {n - k} (residual above {self.threshold:g} px)")
        lines.append(f"residual: inliers RMS {self.rms:.4g} px, max {self.max:.4g} px "
                     f"[robust loss {self.loss}, scale {self.scale:g} px]")
        if len(self.tried) > 1:
            lines.append("tried:    " + "; ".join(f"{s} -> robust cost {c:.4g}" for s, c in self.tried))
        lines.append(f"nlopt:    robust pass: {self.robust.describe()}")
        if self.refit is not None:
            lines.append(f"          inlier refit: {self.refit.describe()}")
        lines.append(f"time:     {self.seconds:.2f} s")
        if per_point:
            lines.append("per point (px):")
            for label, (x, y), r, ok in zip(self.points.labels, self.points.xy, self.residuals, self.inlier):
                lines.append(f"  {label:>9}  ({x:9.2f}, {y:9.2f})  {r:10.4g}{'' if ok else '  outlier'}")
        if not self.ok:
            lines.append(f"verdict:  NOT A GOOD FIT: only {k} of {n} points agree with the fitted camera within "
                         f"{self.threshold:g} px; check the points, the model, or raise --scale")
        else:
            lines.append("verdict:  OK")
        return lines


class _Calibration:
    def __init__(self, space: ParamSpace, pts: PointSet, pose: bool):
        self.space, self.pts, self.pose = space, pts, pose
        self.penalty = float(np.hypot(*space.size))
        self.nlens = len(space.names)

    def camera(self, x, combo) -> Camera | None:
        lens = self.space.try_make(x[: self.nlens], combo)
        if lens is None:
            return None
        pose = Pose.from_ypr(*x[self.nlens:]) if self.pose else Pose()
        return Camera(lens, pose)

    def residuals(self, cam: Camera | None) -> np.ndarray:
        if cam is None:
            return np.full(len(self.pts.xy), self.penalty)
        d = self.pts.dirs @ cam.pose.rotation  # world -> camera
        p, ok = project(cam.lens, d)
        r = np.hypot(p[:, 0] - self.pts.xy[:, 0], p[:, 1] - self.pts.xy[:, 1])
        return np.where(ok & np.isfinite(r), np.minimum(r, 1e6 * self.penalty), self.penalty)

    def cost(self, combo, loss: str, scale: float, mask: np.ndarray | None = None):
        rho = LOSSES[loss]

        def f(x):
            r = self.residuals(self.camera(x, combo))
            if mask is not None:
                r = r[mask]
            return float(scale ** 2 * np.sum(rho((r / scale) ** 2)) / len(r))
        return f


def fit_points(
    points: PointSet,
    model: str,
    size: tuple[int, int],
    *,
    free: Sequence[str] | str | None = None,
    bounds: Mapping[str, tuple[float, float]] | str | None = None,
    pose: bool = False,
    loss: str = "cauchy",
    scale: float = 1.0,
    outlier: float | None = None,
    global_start: str | None = "auto",
) -> PointsFit:
    """Fit the model spec ``model`` (image ``size``) to measured points, robustly.

    A robust fit (the ``loss``) finds the inliers, then a least-squares fit on them refines the answer.

    Parameters
    ----------
    points : PointSet
        Pixels and the unit direction each one sees (:func:`read_points` reads them from a CSV).
    model : str
        The model to fit, as a spec; the values it gives are start values (fitted) or fixed values.
    size : tuple of int
        (W, H) of the camera's image.
    free : str or sequence of str, optional
        The parameters to fit; by default the model's own choice.
    bounds : mapping or str, optional
        Search ranges, ``{"fov": (90, 200)}`` or ``"fov=90:200"``.
    pose : bool
        Also fit the camera's yaw, pitch and roll (the directions are then world directions).
    loss : str
        The robust loss of the first fit: ``"cauchy"``, ``"huber"``, ``"soft_l1"``, ``"arctan"`` or
        ``"linear"`` (none).
    scale : float
        The loss's scale in pixels: residuals well below it count fully.
    outlier : float, optional
        The residual in pixels beyond which a point is an outlier (default ``3 * scale``).
    global_start : str, optional
        As for :func:`~lenslab.fit.lens.fit_lens` (``"auto"`` adds a DIRECT-L search when the local one
        leaves more than a tenth of the points beyond the outlier threshold).

    Returns
    -------
    PointsFit
        The calibrated ``camera`` (and ``lens``), every point's residual in pixels and which are inliers.

    Raises
    ------
    lenslab.errors.FitError
        An unknown loss, a scale that is not positive, or fewer points than parameters plus one.

    Examples
    --------
    Points measured through a 170-degree equisolid fisheye give its field back:

    >>> import numpy as np, lenslab
    >>> from lenslab.fit import PointSet, fit_points
    >>> truth = lenslab.make_lens("fisheye:fov=170,mapping=equisolid", (64, 64))
    >>> xy = np.stack(np.meshgrid(np.arange(4.5, 64, 8), np.arange(4.5, 64, 8)), -1).reshape(-1, 2)
    >>> dirs, seen = truth.pixel_to_dir(xy)
    >>> points = PointSet(xy[seen], dirs[seen], [f"point {i}" for i in range(int(seen.sum()))])
    >>> fit = fit_points(points, "fisheye:fov=120,mapping=equisolid", (64, 64), free="fov")
    >>> round(fit.lens.fov, 6), bool(fit.inlier.all()), float(fit.residuals.max()) < 1e-6
    (170.0, True, True)
    """
    t0 = time.perf_counter()
    if loss not in LOSSES:
        raise FitError(f"unknown robust loss {loss!r}; choose one of {', '.join(LOSSES)}")
    if not scale > 0:
        raise FitError(f"the loss scale must be positive (pixels), got {scale}")
    threshold = float(outlier if outlier is not None else 3.0 * scale)
    space = build_space(model, size, free=free, bounds=bounds)
    names = space.names + (POSE_NAMES if pose else ())
    if len(points.xy) < len(names) + 1:
        raise FitError(f"{len(points.xy)} points cannot determine {len(names)} parameters; "
                       f"measure at least {len(names) + 1} (many more for a robust fit)")
    start = np.concatenate([space.start, np.zeros(3 if pose else 0)])
    lower = np.concatenate([space.lower, [b[0] for b in POSE_BOUNDS][: 3 if pose else 0]])
    upper = np.concatenate([space.upper, [b[1] for b in POSE_BOUNDS][: 3 if pose else 0]])
    cal = _Calibration(space, points, pose)
    best = None
    tried: list[tuple[str, float]] = []
    for combo in space.combinations():
        f = cal.cost(combo, loss, scale)
        attempts = []
        if global_start in (None, "auto"):
            attempts.append(_attempt(f, start, lower, upper, names, None))
        if global_start is not None:
            local_ok = attempts and _inlier_fraction(cal, attempts[0].x, combo, threshold) >= 0.9
            if global_start != "auto" or not local_ok:
                attempts.append(_attempt(f, start, lower, upper, names,
                                         "direct-l" if global_start == "auto" else global_start))
        res = min(attempts, key=lambda r: r.value)
        cam = cal.camera(res.x, combo)
        tried.append((fitted_text(cam.lens, SHARE * scale)[0] if cam is not None else f"{space.model} {combo}",
                      res.value))
        if best is None or res.value < best[1].value:
            best = (combo, res)
    combo, robust = best
    r = cal.residuals(cal.camera(robust.x, combo))
    inlier = r <= threshold
    refit = None
    x = robust.x
    if inlier.sum() >= len(names) + 1:
        f = cal.cost(combo, "linear", 1.0, inlier)
        refit = _attempt(f, robust.x, lower, upper, names, None)
        if refit.value <= f(robust.x):
            x = refit.x
        cam = cal.camera(x, combo)
        r = cal.residuals(cam)
        inlier = r <= threshold
    cam = cal.camera(x, combo)
    if cam is None:
        raise FitError(f"no parameter values make a valid {space.model} lens for these points")
    return PointsFit(cam, r, inlier, points, names, loss, scale, threshold, robust, refit,
                     time.perf_counter() - t0, tried)


def _inlier_fraction(cal: _Calibration, x, combo, threshold) -> float:
    return float(np.mean(cal.residuals(cal.camera(x, combo)) <= threshold))


def _attempt(f, start, lower, upper, names, global_start) -> OptimizeResult:
    try:
        return minimize(f, start, lower, upper, names=names, method="bobyqa", global_start=global_start,
                        stopval=1e-30)
    except FitError as exc:
        if exc.best is not None:
            return exc.best
        raise
