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

The answer is always a field the model accepts, written as a spec that parses back to the same lens.
Two cases have no answer to search for:

- ``fill`` when the output has no hole even at the widest field its model allows (the source covers
  every direction the output can look along, e.g. a full panorama): there is nothing to fill, and the
  field of view is kept as given;
- an answer within :data:`EDGE_RTOL` of the end of the model's range (``cover`` from a 180-degree
  fisheye into a perspective view would need a 179.997-degree perspective, a view that is all
  stretched rim): no usable field does it, and :class:`FitError` says so.

A model whose parameters hold no field of view (a cube map, a calibrated camera) cannot be scaled:
:func:`autoscale` raises :class:`FitError` naming it, and :func:`autoscale_camera` reports that and
keeps the camera as given.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from lenslab.errors import FitError, LensError
from lenslab.fit.coverage import Criterion
from lenslab.lenses import Camera
from lenslab.lenses.core.base import Lens

MODES = ("fill", "cover")
RTOL = 1e-7  # relative width of the final bracket on the scale
# an answer this close (relative) to the end of the model's range is that end: a view that has to stretch
# to its model's limit (a perspective of 179.997 degrees) shows nothing usable
EDGE_RTOL = 1e-4


RANGES = (("lon_min", "lon_max"), ("lat_min", "lat_max"))


def has_field(lens: Lens) -> bool:
    """Whether the lens's parameters hold a field of view that auto-scale can scale."""
    values = lens.param_values()
    return (isinstance(values.get("fov"), float)
            or {"lon_min", "lon_max", "lat_min", "lat_max"} <= values.keys())


def no_field_message(lens: Lens) -> str:
    return (f"cannot auto-scale a {lens.name} output: its parameters hold no field of view to scale; "
            "its field is kept as given")


def scaled_lens(lens: Lens, s: float) -> Lens | None:
    """The lens with its field scaled by ``s`` (None where the model does not allow that field, or where
    its spec would not read back as the same lens)."""
    from lenslab.lenses import make_lens

    values = lens.param_values()
    if isinstance(values.get("fov"), float):
        values["fov"] = values["fov"] * s
        for alt in ("vfov", "dfov"):  # the other ways of giving the same field, when given
            if values.get(alt):
                values[alt] = values[alt] * s
    elif {"lon_min", "lon_max", "lat_min", "lat_max"} <= values.keys():
        for lo, hi in RANGES:
            c, half = 0.5 * (values[lo] + values[hi]), 0.5 * (values[hi] - values[lo]) * s
            values[lo], values[hi] = c - half, c + half
    else:
        raise FitError(no_field_message(lens))
    try:
        out = type(lens)(lens.width, lens.height, **values)
        # the lens its printed spec reads back as (the spec rounds; it can even leave the model's range):
        # what is tested is what the user is told
        return make_lens(out.spec(), (out.width, out.height))
    except LensError:
        return None


def field_description(lens: Lens) -> str:
    v = lens.param_values()
    if "fov" in v:
        return f"fov={v['fov']:.10g}"
    return ", ".join(f"{k}={v[k]:.10g}" for k in ("lon_min", "lon_max", "lat_min", "lat_max") if k in v)


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
    pixels: int = 0  # pixels the criterion is counted over (the output's for fill, the source's for cover)
    kept: bool = False  # nothing to fill: the field was kept as given

    @property
    def lens(self) -> Lens:
        return self.camera.lens

    def report(self, verbose: bool = False) -> list[str]:
        """What a user reads: old -> new field, and the share of empty (or cropped) pixels around it;
        with ``verbose``, the search's own figures too."""
        if self.kept:
            lines = [f"autoscale {self.mode}: {self.notes[0]} ({self.before} kept)"]
        else:
            beyond = "wider" if self.mode == "fill" else "narrower"
            if self.bad_one_percent_beyond < 0:
                then = f"a 1% {beyond} field is outside what the model allows"
            else:
                share = 100.0 * self.bad_one_percent_beyond / max(1, self.pixels)
                then = (f"a 1% {beyond} field would leave {share:.2g}% of the output's pixels empty"
                        if self.mode == "fill" else
                        f"a 1% {beyond} field would crop {share:.2g}% of the source's pixels")
            what = "no empty pixel" if self.mode == "fill" else "every source pixel shown"
            lines = [f"autoscale {self.mode}: {self.before} -> {self.after}: {what}; {then}"]
        if verbose:
            lines += [f"  scale {self.scale:.10g}; {self.bad_at_scale} failing pixels at it; "
                      f"{self.evaluations} evaluations in {self.seconds:.2f} s; COBYLA check: {self.cobyla}"]
            lines += [f"  note: {n}" for n in self.notes[1 if self.kept else 0:]]
        return lines


def autoscale(src: Camera, dst: Camera, mode: str = "fill", samples: int = 1, rtol: float = RTOL) -> AutoscaleResult:
    """Scale ``dst``'s field of view so that the warp from ``src`` fills it (``fill``) or shows all of ``src``
    (``cover``); the module's description gives the search and its checks.

    Parameters
    ----------
    src : lenslab.lenses.Camera
        The camera of the source image.
    dst : lenslab.lenses.Camera
        The output camera; its lens's field of view (``fov``, or a focal length) is scaled.
    mode : str
        ``"fill"``: the widest field with no output pixel left empty; ``"cover"``: the narrowest that
        shows every source pixel.
    samples : int
        Samples per output pixel the criterion checks (as the warp will take them).
    rtol : float
        Relative precision of the scale.

    Returns
    -------
    AutoscaleResult
        The ``scale``, the output ``camera`` with the scaled lens, its field before and after, and the
        evidence (pixels breaking the criterion at the answer and 1% beyond it).

    Raises
    ------
    lenslab.errors.FitError
        An unknown mode, a lens with no field of view to scale, or no usable scale.

    Examples
    --------
    A fisheye that shows all of a square 90-degree view must reach its corners, ``atan(sqrt 2)`` off
    axis: a field of ``2 atan(sqrt 2)`` = 109.4712 degrees.

    >>> import math, lenslab
    >>> from lenslab.fit import autoscale
    >>> view = lenslab.Camera.from_spec("perspective:fov=90", (64, 64))
    >>> fish = lenslab.Camera.from_spec("fisheye:fov=180", (64, 64))
    >>> result = autoscale(view, fish, mode="cover")
    >>> round(result.camera.lens.fov, 4), round(math.degrees(2 * math.atan(math.sqrt(2))), 4)
    (109.4712, 109.4712)
    """
    t0 = time.perf_counter()
    if mode not in MODES:
        raise FitError(f"unknown autoscale mode {mode!r}; choose one of {', '.join(MODES)}")
    base = dst.lens
    if not has_field(base):
        raise FitError(no_field_message(base))
    base = scaled_lens(base, 1.0) or base  # as its spec reads back
    crit = Criterion(src, Camera(base, dst.pose), mode, int(samples))
    w, h = dst.size if mode == "fill" else src.size

    def feasible(s: float) -> bool:
        return crit.count(scaled_lens(base, s)) == 0

    def exists(s: float) -> bool:
        return scaled_lens(base, s) is not None

    notes: list[str] = []
    for _ in range(50):  # search on the active set; verify on every sample; repeat with the failures added
        good, edge = _search(feasible, exists, mode, rtol, base, src)
        fail = crit.full_failures(scaled_lens(base, good))
        if not fail.any():
            if edge == "open":  # fill holds up to the widest field the model allows: nothing to fill
                good = 1.0
            break
        crit.activate(fail)
    else:  # pragma: no cover
        raise FitError("auto-scale did not settle: every search found new failing pixels")
    lens = scaled_lens(base, good)
    if edge == "open":
        notes.append(f"the source covers every direction the {base.name} output can look along, up to the "
                     "widest field its model allows: there is nothing to fill, and the field of view is kept")
        return AutoscaleResult(mode, 1.0, Camera(lens, dst.pose), field_description(base), field_description(lens),
                               0, -1, crit.evaluations + crit.full_evaluations, "not needed",
                               time.perf_counter() - t0, notes, w * h, kept=True)
    if edge == "limit":
        raise FitError(_at_limit(mode, base, lens, src))
    up = mode == "fill"
    beyond_lens = scaled_lens(base, good * (1.01 if up else 1 / 1.01))
    bad_beyond = crit.pixels(beyond_lens) if beyond_lens is not None else -1
    cobyla = _cobyla_check(crit, base, good, up)
    return AutoscaleResult(mode, float(good), Camera(lens, dst.pose), field_description(base),
                           field_description(lens), 0, bad_beyond, crit.evaluations + crit.full_evaluations,
                           cobyla, time.perf_counter() - t0, notes, w * h)


def _search(feasible, exists, mode: str, rtol: float, base: Lens, src: Camera) -> tuple[float, str | None]:
    """Bracket and bisect the scale where ``feasible`` changes; returns the feasible end and what the
    search met: ``"open"`` (feasible up to the model's widest field, fill), ``"limit"`` (the answer lies
    within :data:`EDGE_RTOL` of the model's range end) or None."""
    # fill: feasible below the answer, infeasible above; cover: the reverse
    up = mode == "fill"
    toward_bad = 2.0 if up else 0.5
    good: float | None = None
    bad: float | None = None
    edge: float | None = None
    if feasible(1.0):
        good = 1.0
        for _ in range(64):
            nxt = good * toward_bad
            if not exists(nxt):
                edge = _range_edge(exists, good, nxt)
                if feasible(edge):
                    if up:
                        return edge, "open"
                    good = edge
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
    if edge is not None and abs(good / edge - 1.0) < EDGE_RTOL:
        return good, "limit"
    return good, None


def _at_limit(mode: str, base: Lens, lens: Lens, src: Camera) -> str:
    if mode == "cover":
        return (f"no usable field of view of the {base.name} output shows all of the source {src.lens.name}: it "
                f"would take {field_description(lens)}, the very end of what the model allows; use a wider "
                "model (a fisheye or equirect) or --autoscale fill")
    return (f"no usable field of view of the {base.name} output is free of holes: it would take "
            f"{field_description(lens)}, the very end of what the model allows (check the cameras' orientations)")


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
            "model (fisheye or equirect) or --autoscale fill")


def _cobyla_check(crit: Criterion, base: Lens, s: float, grow: bool) -> str:
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


def autoscale_camera(src: Camera, dst: Camera, mode: str = "fill", samples: int = 1, report=None,
                     verbose: bool = False) -> Camera:
    """The output camera of a warp with its field auto-scaled (see :func:`autoscale`).

    For ``lenslab warp --autoscale``: a batch of images of one geometry computes the scale once.
    ``report``, if given, is called with each line of the summary (the search's figures too with
    ``verbose``). A lens with no field of view to scale is reported and kept as given.
    """
    if not has_field(dst.lens):
        if report is not None:
            report(no_field_message(dst.lens))
        return dst
    key = (src.lens.spec(), src.size, src.pose.rotation.tobytes(), dst.lens.spec(), dst.size,
           dst.pose.rotation.tobytes(), mode, int(samples))
    result = _CAMERA_CACHE.get(key)
    if result is None:
        result = _CAMERA_CACHE[key] = autoscale(src, dst, mode, samples)
        if report is not None:
            for line in result.report(verbose):
                report(line)
    return Camera(result.lens, dst.pose)
