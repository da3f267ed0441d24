"""Many images, one geometry: plans whose maps are computed once and reused.

A batch of frames from the same camera into the same output costs one map computation; every later
frame is a sampling pass only. :class:`PlanCache` keeps the plans of the geometries seen so far (a
batch usually has one), with their maps cached while they fit in ``max_map_bytes``; a geometry whose
maps would not fit is warped band by band as usual, without caching.

Files warped at once on threads share the cache: the first to ask for a geometry builds its plan and maps,
every other thread that asks for it meanwhile waits for that build and reuses it (or fails with its error),
so each geometry's maps are computed once however the threads interleave.
"""

from __future__ import annotations

import threading
from collections import OrderedDict

from lenslab.lenses import Camera
from lenslab.warp.engine import WarpPlan

MAX_MAP_BYTES = 1 << 30  # 1 GiB of cached maps at most


def geometry_key(src: Camera, dst: Camera) -> str:
    """A string identifying a (source camera, destination camera) pair, sizes and poses included: their
    descriptions (``to_dict``) with every table's keys sorted, each number as a Python float or int, anything else
    by ``str`` (without JSON's encoder: a clip's warp does not load it)."""
    return repr(_canonical([src.to_dict(), dst.to_dict()]))


def _canonical(value):
    if isinstance(value, dict):
        return "table", tuple(sorted((str(k), _canonical(v)) for k, v in value.items()))
    if isinstance(value, (list, tuple)):
        return "list", tuple(_canonical(v) for v in value)
    if value is None or isinstance(value, (bool, str)):
        return value
    if isinstance(value, int):
        return int(value)
    return float(value) if isinstance(value, float) else str(value)


def map_bytes_estimate(dst: Camera, samples: int, antialias: bool, filter: str = "bilinear") -> int:
    """Bytes the cached maps of a plan will take (9 per sample, 25 with the footprint, 12 for the taps of
    a one-sample bilinear map: :mod:`lenslab.warp.taps`)."""
    per = 25 if antialias else (12 if samples == 1 and filter == "bilinear" else 9)
    return dst.width * dst.height * samples * per


def _own(exc: BaseException) -> BaseException:
    """A copy of ``exc`` for another thread to raise: its own traceback and file name (the funnel marks the
    file an error belongs to on the exception); ``exc`` itself when it does not copy faithfully."""
    import copy

    try:
        clone = copy.copy(exc)
    except Exception:  # noqa: BLE001 - an exception whose class does not rebuild from its args
        return exc
    return clone if type(clone) is type(exc) and str(clone) == str(exc) else exc


class Future:
    """A geometry's plan, built or being built: the threads that ask for it meanwhile wait for the builder's plan or
    error (the part of ``concurrent.futures.Future`` the cache uses, without loading that package at a command's
    start)."""

    def __init__(self):
        self._done = threading.Event()
        self._plan = self._error = None

    def set_result(self, plan) -> None:
        self._plan = plan
        self._done.set()

    def set_exception(self, exc: BaseException) -> None:
        self._error = exc
        self._done.set()

    def done(self) -> bool:
        return self._done.is_set()

    def result(self, timeout: float | None = None):
        if not self._done.wait(timeout):
            raise TimeoutError("the plan is still being built")
        if self._error is not None:
            raise self._error
        return self._plan


class PlanCache:
    """Plans by geometry, least recently used dropped first (``keep`` geometries at most)."""

    def __init__(self, keep: int = 2, max_map_bytes: int = MAX_MAP_BYTES, factory=WarpPlan, **options):
        self.factory = factory  # the plan class (e.g. compat_v360.V360Plan)
        self.keep = max(1, int(keep))
        self.max_map_bytes = int(max_map_bytes)
        self.options = options
        self._plans: OrderedDict[str, Future] = OrderedDict()  # a geometry's plan, built or being built
        self._lock = threading.Lock()
        self.built = 0  # plans made (map computations), for reporting

    def plan(self, src: Camera, dst: Camera) -> WarpPlan:
        """This geometry's plan, its maps computed (when they are kept): built by the first caller, waited for
        by any other thread that asks while it is built (which then fails with the builder's error, if any)."""
        key = geometry_key(src, dst)
        with self._lock:
            pending = self._plans.get(key)
            if pending is None:
                self._plans[key] = mine = Future()
                while len(self._plans) > self.keep:  # a dropped build still reaches those waiting for it
                    self._plans.popitem(last=False)
            else:
                self._plans.move_to_end(key)
        if pending is not None:
            try:
                return pending.result()
            except BaseException as exc:  # the builder's error, raised as this caller's own
                own = _own(exc)
                if own is exc:
                    raise
                raise own from exc
        try:
            plan = self._build(src, dst)
        except BaseException as exc:
            with self._lock:  # a later file of this geometry tries again
                if self._plans.get(key) is mine:
                    del self._plans[key]
            mine.set_exception(exc)
            raise
        mine.set_result(plan)
        return plan

    def _build(self, src: Camera, dst: Camera) -> WarpPlan:
        """A new plan of this geometry, its maps computed now when they fit the cache."""
        cache = map_bytes_estimate(dst, self.options.get("samples", 1), self.options.get("antialias", False),
                                   self.options.get("filter", "bilinear")) <= self.max_map_bytes // self.keep
        plan = self.factory(src, dst, cache=cache, **self.options)
        plan.prepare()
        with self._lock:
            self.built += 1
        return plan

    def warp(self, image, src: Camera, dst: Camera, progress=None, into=None, alpha: bool | None = None,
             on_band=None, plan: WarpPlan | None = None):
        """Warp ``image`` with the (cached) plan of this geometry; see :func:`lenslab.warp.warp` (``into`` and
        ``on_band``: see :meth:`lenslab.warp.engine.WarpPlan.run`). ``plan``: this geometry's :meth:`plan`, held by
        a caller that warps many frames (keying the cameras again costs 0.1 ms a frame)."""
        plan = self.plan(src, dst) if plan is None else plan
        return plan.run(image, progress=progress, into=into, alpha_channel=alpha, on_band=on_band)

    def warp_frame(self, image, src: Camera, dst: Camera, progress=None, into=None, alpha: bool | None = None,
                   on_band=None, plan: WarpPlan | None = None):
        """The step a still image and every frame of a clip share, between decoding to linear light (the
        format's reader) and encoding (its writer): warp, alpha settled, split into ``(premultiplied
        colour, alpha)`` (the image's own alpha, or the coverage). ``into``: output arrays to reuse;
        ``on_band(rows, sl)``: the output's final rows as the bands draw them (a clip's encoder takes each band
        on its thread; the colour of an image without alpha channel is its rows as they are); ``plan``: as
        :meth:`warp`'s."""
        from lenslab.io.alpha import split_alpha

        return split_alpha(*self.warp(image, src, dst, progress=progress, into=into, alpha=alpha, on_band=on_band,
                                      plan=plan), alpha=alpha)


__all__ = ["PlanCache", "geometry_key", "MAX_MAP_BYTES"]
