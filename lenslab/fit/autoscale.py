"""Auto-scale: the output field of view that fills the output with the source, or shows all of it.

When a warp changes the lens (correcting barrel distortion, cutting a perspective view out of a
partial panorama), the output's field of view decides between two kinds of loss:

- ``fill`` (default): the *widest* output field at which every output pixel sees the source, so the
  output has no hole (no pixel whose ray exists but falls outside the source); any wider field leaves
  holes. This is lensfun's auto-scale for distortion correction.
- ``cover``: the *narrowest* output field that still shows every pixel of the source; any narrower
  field crops some of it.

The field is scaled by a factor ``s`` applied to the output lens's angular parameters: ``fov`` (of the
lens, or of the base model of a bent lens such as swirl or distortion), or the longitude and latitude
ranges of an equirect (scaled about their centre). A pixel counts as seen when every one of its
``samples`` sub-pixel sample positions (the warp's stratified pattern) is.

The scale is found by a bracketed search on the exact criterion: grow or shrink ``s`` by factors of
two until the criterion changes, then bisect (in log scale) until the bracket is narrower than
``rtol``. Each step tests the output's border ring and a sparse grid first, and the whole pixel grid
only when those pass; the answer is verified on every pixel. nlopt's COBYLA, started at the answer
with the constraint "no hole" (or "nothing cropped"), then confirms that no better feasible scale is
within reach; a disagreement is reported.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from lenslab.errors import FitError, LensError
from lenslab.lenses import Camera, rotation_between, sample_offsets
from lenslab.lenses.base import Lens

MODES = ("fill", "cover")
RTOL = 1e-7  # relative width of the final bracket on the scale
SPARSE = 8  # the sparse pre-check tests every SPARSE-th pixel (plus the border ring)


def scaled_lens(lens: Lens, s: float) -> Lens | None:
    """The lens with its field scaled by ``s`` (None where the model does not allow that field)."""
    values = lens.param_values()
    if "fov" in values and isinstance(values["fov"], float):
        values["fov"] = values["fov"] * s
        if values.get("vfov"):
            values["vfov"] = values["vfov"] * s
    elif {"lon_min", "lon_max", "lat_min", "lat_max"} <= values.keys():
        for lo, hi in (("lon_min", "lon_max"), ("lat_min", "lat_max")):
            c, half = 0.5 * (values[lo] + values[hi]), 0.5 * (values[hi] - values[lo]) * s
            values[lo], values[hi] = c - half, c + half
    else:
        raise FitError(f"cannot auto-scale a {lens.name} output: it has no field of view to scale; "
                       "use a perspective, fisheye, equirect or other lens with a fov")
    try:
        return type(lens)(lens.width, lens.height, **values)
    except LensError:
        return None


def field_description(lens: Lens) -> str:
    v = lens.param_values()
    if "fov" in v:
        return f"fov={v['fov']:.10g}"
    return ", ".join(f"{k}={v[k]:.10g}" for k in ("lon_min", "lon_max", "lat_min", "lat_max") if k in v)


def _positions(width: int, height: int, stride: int, samples: int) -> np.ndarray:
    """Sub-pixel sample positions of the border ring plus every ``stride``-th pixel: (n, 2)."""
    xs = np.arange(width)
    ys = np.arange(height)
    if stride > 1:
        xs = np.unique(np.concatenate([xs[::stride], [width - 1]]))
        ys = np.unique(np.concatenate([ys[::stride], [height - 1]]))
    gx, gy = np.meshgrid(xs, ys)
    pix = np.stack([gx.ravel(), gy.ravel()], axis=-1).astype(np.float64)
    if stride > 1:  # the full border ring too
        ring = np.concatenate([
            np.stack([np.arange(width), np.zeros(width)], -1), np.stack([np.arange(width), np.full(width, height - 1)], -1),
            np.stack([np.zeros(height), np.arange(height)], -1), np.stack([np.full(height, width - 1), np.arange(height)], -1),
        ]).astype(np.float64)
        pix = np.unique(np.concatenate([pix, ring]), axis=0)
    off = sample_offsets(samples, (), None)  # (S, 2) in [0, 1)
    return (pix[:, None, :] + off[None, :, :]).reshape(-1, 2)


class _Criterion:
    """Counts holes (fill) or cropped source samples (cover) at a scale.

    Tests run on an *active* set (the border ring and a sparse grid, plus every sample that has
    failed a full check so far); :meth:`full_failures` checks every sample.
    """

    def __init__(self, src: Camera, dst: Camera, mode: str, samples: int):
        self.src, self.dst, self.mode = src, dst, mode
        self.rot = rotation_between(src, dst)  # dst camera space -> src camera space
        w, h = dst.size if mode == "fill" else src.size
        self.samples = samples
        self.full = _positions(w, h, 1, samples)
        self.active = _positions(w, h, SPARSE, samples)
        self.evaluations = 0
        self.full_evaluations = 0
        if mode == "cover":  # source rays, in the output's camera space
            d, ok = src.lens.pixel_to_dir(self.full)
            self.full_ok = ok
            self.full_dirs = np.where(ok[:, None], d @ self.rot, 0.0)
            d, ok = src.lens.pixel_to_dir(self.active)
            self.active_dirs = d[ok] @ self.rot

    def _seen(self, lens: Lens, pts: np.ndarray | None, dirs: np.ndarray | None) -> np.ndarray:
        if self.mode == "fill":
            d, ok = lens.pixel_to_dir(pts)
            seen = np.ones(len(pts), dtype=bool)
            seen[ok] = self.src.lens.dir_to_pixel(d[ok] @ self.rot.T)[1]
            return seen
        return lens.dir_to_pixel(dirs)[1]

    def count(self, lens: Lens | None) -> int:
        """Failing samples of the active set (a huge number where the model refuses the scale)."""
        self.evaluations += 1
        if lens is None:
            return 1 << 40
        if self.mode == "fill":
            return int((~self._seen(lens, self.active, None)).sum())
        return int((~self._seen(lens, None, self.active_dirs)).sum())

    def full_failures(self, lens: Lens) -> np.ndarray:
        """Mask over every sample of the ones that fail."""
        self.full_evaluations += 1
        if self.mode == "fill":
            return ~self._seen(lens, self.full, None)
        fail = np.zeros(len(self.full), dtype=bool)
        fail[self.full_ok] = ~self._seen(lens, None, self.full_dirs[self.full_ok])
        return fail

    def activate(self, fail: np.ndarray) -> None:
        """Add failing samples to the active set (so the next search respects them)."""
        self.active = np.concatenate([self.active, self.full[fail]])
        if self.mode == "cover":
            self.active_dirs = np.concatenate([self.active_dirs, self.full_dirs[fail]])

    def pixels(self, lens: Lens | None) -> int:
        """Number of *pixels* (not samples) that fail, on every pixel."""
        if lens is None:
            return -1
        return int(self.full_failures(lens).reshape(-1, self.samples).any(axis=1).sum())


@dataclass
class AutoscaleResult:
    """The chosen scale, the output camera it gives, and the evidence."""

    mode: str
    scale: float
    camera: Camera  # the output camera with the scaled lens
    before: str  # the output lens's field before and after
    after: str
    bad_at_scale: int  # pixels breaking the criterion at the answer (0)
    bad_one_percent_beyond: int  # ... 1% beyond it (wider for fill, narrower for cover); -1 if not allowed
    evaluations: int
    cobyla: str
    seconds: float
    notes: list[str] = field(default_factory=list)

    @property
    def lens(self) -> Lens:
        return self.camera.lens

    def report(self) -> list[str]:
        what = "holes" if self.mode == "fill" else "cropped source pixels"
        beyond = "wider" if self.mode == "fill" else "narrower"
        lines = [f"autoscale {self.mode}: scale {self.scale:.8g} ({self.before} -> {self.after})",
                 f"  {what}: {self.bad_at_scale} at this scale, "
                 + (f"{self.bad_one_percent_beyond} with a 1% {beyond} field" if self.bad_one_percent_beyond >= 0
                    else f"a 1% {beyond} field is outside the model's range"),
                 f"  {self.evaluations} evaluations, {self.seconds:.2f} s; COBYLA check: {self.cobyla}"]
        lines += [f"  note: {n}" for n in self.notes]
        return lines


def autoscale(src: Camera, dst: Camera, mode: str = "fill", samples: int = 1, rtol: float = RTOL) -> AutoscaleResult:
    """Scale ``dst``'s field of view so that the warp from ``src`` fills it (``fill``) or shows all of ``src``
    (``cover``); see the module docstring. Raises :class:`FitError` when no scale can do it."""
    t0 = time.perf_counter()
    if mode not in MODES:
        raise FitError(f"unknown autoscale mode {mode!r}; choose one of {', '.join(MODES)}")
    crit = _Criterion(src, dst, mode, int(samples))
    base = dst.lens
    scaled_lens(base, 1.0)  # raises for a lens without a field to scale

    def feasible(s: float) -> bool:
        return crit.count(scaled_lens(base, s)) == 0

    def exists(s: float) -> bool:
        return scaled_lens(base, s) is not None

    notes: list[str] = []
    for _ in range(50):  # search on the active set; verify on every sample; repeat with the failures added
        good = _search(feasible, exists, mode, rtol, notes, base, src)
        fail = crit.full_failures(scaled_lens(base, good))
        if not fail.any():
            break
        crit.activate(fail)
    else:  # pragma: no cover
        raise FitError("auto-scale did not settle: every search found new failing pixels")
    lens = scaled_lens(base, good)
    bad_here = 0  # verified on every sample above
    up = mode == "fill"
    beyond = good * (1.01 if up else 1 / 1.01)
    beyond_lens = scaled_lens(base, beyond)
    bad_beyond = crit.pixels(beyond_lens) if beyond_lens is not None else -1
    cobyla = _cobyla_check(crit, base, good, up)
    return AutoscaleResult(mode, float(good), Camera(lens, dst.pose), field_description(base),
                           field_description(lens), bad_here, bad_beyond, crit.evaluations + crit.full_evaluations,
                           cobyla,
                           time.perf_counter() - t0, notes)


def _search(feasible, exists, mode: str, rtol: float, notes: list[str], base: Lens, src: Camera) -> float:
    """Bracket and bisect the scale where ``feasible`` changes; returns the feasible end."""
    # fill: feasible below the answer, infeasible above; cover: the reverse
    up = mode == "fill"
    toward_bad = 2.0 if up else 0.5
    good: float | None = None
    bad: float | None = None
    if feasible(1.0):
        good = 1.0
        for _ in range(64):
            nxt = good * toward_bad
            if not exists(nxt):
                edge = _range_edge(exists, good, nxt)
                if feasible(edge):
                    good = edge
                    note = "the criterion holds up to the end of the model's range: its limit was taken"
                    if note not in notes:
                        notes.append(note)
                else:
                    bad = edge
                break
            if not feasible(nxt):
                bad = nxt
                break
            good = nxt
    else:
        bad = 1.0
        for _ in range(64):
            nxt = bad / toward_bad
            if not exists(nxt):
                edge = _range_edge(exists, bad, nxt)
                if not feasible(edge):
                    raise FitError(_impossible(mode, base, src))
                good = edge
                break
            if feasible(nxt):
                good = nxt
                break
            bad = nxt
        if good is None:
            raise FitError(_impossible(mode, base, src))
    if good is None:  # pragma: no cover - 64 doublings of a field always leave a model's range
        raise FitError(_impossible(mode, base, src))
    if bad is not None:
        lo, hi = sorted([good, bad])
        while hi / lo - 1.0 > rtol:
            mid = float(np.sqrt(lo * hi))
            if feasible(mid) == up:
                lo = mid
            else:
                hi = mid
        good = lo if up else hi
    return good


def _range_edge(exists, inside: float, outside: float) -> float:
    """The last scale the model allows between ``inside`` (allowed) and ``outside`` (not), by bisection."""
    a, b = inside, outside
    for _ in range(80):
        mid = float(np.sqrt(a * b))
        if exists(mid):
            a = mid
        else:
            b = mid
        if abs(b / a - 1.0) < 1e-12:
            break
    return a


def _impossible(mode: str, lens: Lens, src: Camera) -> str:
    if mode == "fill":
        return (f"no field of view of the {lens.name} output is free of holes: even its narrowest view looks "
                f"outside the source {src.lens.name} (check the cameras' orientations)")
    return (f"no field of view of the {lens.name} output shows all of the source {src.lens.name}: use a wider "
            "model (fisheye or equirect) or autoscale fill")


def _cobyla_check(crit: _Criterion, base: Lens, s: float, grow: bool) -> str:
    """Ask COBYLA for a better scale under the same constraint, from the answer; report whether it agrees."""
    from lenslab.fit.optimize import minimize

    lo, hi = s * 0.5, s * 2.0
    if scaled_lens(base, hi) is None:
        hi = s * (1 + 1e-9)
    if scaled_lens(base, lo) is None:
        lo = s * (1 - 1e-9)

    def objective(x):
        return -x[0] if grow else x[0]

    def constraint(x):  # <= 0 when feasible: the fraction of failing samples
        n = crit.count(scaled_lens(base, float(x[0])))
        return float(min(n, 1 << 40))

    try:
        res = minimize(objective, [s], [lo], [hi], names=["scale"], method="cobyla", constraints=[constraint],
                       xtol_rel=1e-9, initial_step=0.01, maxeval=200)
    except FitError as exc:
        return f"not run to the end ({exc})"
    better = (res.x[0] > s * (1 + 1e-6)) if grow else (res.x[0] < s * (1 - 1e-6))
    if better and not crit.full_failures(scaled_lens(base, float(res.x[0]))).any():
        return f"DISAGREES: it found scale {res.x[0]:.8g} feasible ({res.evaluations} evaluations)"
    return f"agrees (best feasible {res.x[0]:.8g}, {res.evaluations} evaluations)"


_CAMERA_CACHE: dict[tuple, AutoscaleResult] = {}


def autoscale_camera(src: Camera, dst: Camera, mode: str = "fill", samples: int = 1, report=None) -> Camera:
    """The output camera of a warp with its field auto-scaled (see :func:`autoscale`).

    For ``lenslab warp --autoscale``: a batch of images of one geometry computes the scale once.
    ``report``, if given, is called with each line of the summary.
    """
    key = (src.lens.spec(), src.size, src.pose.rotation.tobytes(), dst.lens.spec(), dst.size,
           dst.pose.rotation.tobytes(), mode, int(samples))
    result = _CAMERA_CACHE.get(key)
    if result is None:
        result = _CAMERA_CACHE[key] = autoscale(src, dst, mode, samples)
        if report is not None:
            for line in result.report():
                report(line)
    return Camera(result.lens, dst.pose)
