"""The warp job: one file warped as ``lenslab warp`` does it, here or on a cluster worker: an image (read,
warp through the plan cache, develop for the output format, write) or a clip (:mod:`lenslab.jobs.warp.video`).

The maps of a batch are made once per process and geometry (:func:`plans_for`): a local batch shares them
between its threads, a cluster worker keeps them for every later frame it gets (building a map on the
worker costs less than shipping it, see ``lenslab bench cluster``).
"""

from __future__ import annotations

import os
import threading
from dataclasses import dataclass, field
from pathlib import Path
from typing import ClassVar

from lenslab.jobs.job import Job

_CACHE: dict[tuple, object] = {}  # per process: the plans of one batch's geometry, the ST maps read
_CACHE_LOCK = threading.Lock()  # files warped at once on threads share one plan cache


@dataclass(frozen=True)
class WarpJob(Job):
    """What ``lenslab warp`` does to each file: the output lens (``to``, ``size``, pose) or an ST map
    (``stmap``), the source lens (``source``; None: the file's own or a 2:1 panorama), sampling, and how
    the output is written (format, look, alpha)."""

    command: ClassVar[str] = "warp"
    verb: ClassVar[str] = "warped"
    paths: ClassVar[tuple[str, ...]] = ("source", "to", "stmap")

    to: str | None = None
    stmap: str | None = None
    source: str | None = None
    size: tuple[int, int] | None = None
    #: the output's turns in degrees; None: not given (0)
    yaw: float | None = None
    pitch: float | None = None
    roll: float | None = None
    look_at: tuple | str | None = None
    eye: tuple | str | None = None
    filter: str = "bilinear"
    samples: int = 1
    seed: int | None = None
    antialias: bool = False
    exact_map: bool = False
    format: str | None = None
    tone: str = "hable"
    tone_given: bool = False
    exposure: float | str = 0.0
    pixel_type: str | None = None  # --pixel-type (lenslab.jobs.pixel_types); None: half in EXR, the format's own
    no_alpha: bool = False
    allow_parallax: bool = False
    autoscale: str | None = None
    compat: str | None = None
    rotation_order: str = "ypr"
    flip: str | None = None
    source_flip: str | None = None
    quiet: bool = False
    verbose: bool = False
    display: str | None = None
    view: str | None = None
    colorspace: str | None = None
    ocio: str | None = None
    frames: tuple | None = None
    codec: str | None = None
    #: one batch's maps are its own (a process keeps the maps of one batch at a time)
    batch: str = field(default_factory=lambda: os.urandom(8).hex(), compare=False)
    #: False: the job warps one still image, whose maps no later image reuses: none are kept (a band's map
    #: lives in scratch memory while it is drawn)
    keep_maps: bool = True

    @property
    def st(self):
        """The ST map of ``stmap``, read once per process."""
        return st_map(self.stmap)[0]

    def run(self, src: str, dst: str, progress=None) -> None:
        warp_one(src, Path(dst), self, plans_for(self), progress=progress)


#: why a warp writes colour and alpha only
WARP_DROPS = "a warp resamples colour and alpha only (depth, normals and vectors belong to the source camera)"


def warp_one(src_path: str, dst_path: Path, job: WarpJob, cache, progress=None) -> None:
    """Warp ``src_path`` to ``dst_path`` as ``job`` says, with the maps of ``cache``."""
    from lenslab.io import carries_alpha, read
    from lenslab.io.registry import format_for_path, get
    from lenslab.jobs.policy import check_output
    from lenslab.io.alpha import split_alpha
    from lenslab.jobs.stages import check_image
    from lenslab.jobs.warp.cameras import (autoscale_camera, default_output_size, output_camera, place_source,
                                            records_place, source_camera, stored_frame)
    from lenslab.jobs.warp.video import is_video, warp_video

    if is_video(src_path):  # every frame with one map, to a video
        return warp_video(src_path, dst_path, job, cache)
    fmt = get(format_for_path(dst_path, None))
    check_output(dst_path, [src_path, *([job.stmap] if job.stmap else [])], job.overwrite)
    image, meta = read(src_path)
    image = check_image(image, src_path)
    from lenslab.jobs.stages import check_data_channels

    check_data_channels(src_path, meta, image.shape[2], fmt)
    from lenslab.io.exr.extra import warn_dropped

    # depth, normals, motion vectors are measured in the source camera's frame: resampled into another lens
    # they would keep the numbers and lose their meaning
    views = _other_views(src_path, meta, fmt.title)
    warn_dropped(src_path, *views)
    warn_dropped(src_path, [n for n in meta.get("extra_channels") or [] if n not in views[0]], fmt.title, WARP_DROPS)
    if job.stmap:
        from lenslab.stmap import warp_with_st_map

        from lenslab.warp.minification import Looked

        dst, plan = None, Looked()  # the map's footprints, looked at as a plan's are
        import numpy as np

        from lenslab.stmap_frame import frame_for_map

        st, recorded = st_map(job.stmap)
        image = np.ascontiguousarray(frame_for_map(image, meta, (st.shape[1], st.shape[0]), recorded, src_path,
                                                   job.stmap))  # a turned photo: as stored, if the map says so
        if hasattr(progress, "start"):  # a bar with the output's rows as its total (lenslab.jobs.progress)
            progress.start(st.shape[0])
        named = source_alpha = carries_alpha(meta, image.shape[2])
        from lenslab.jobs.warp.output import output_arrays

        into = output_arrays(st.shape[:2], image.shape[2], fmt, job, meta, named)  # (the one image written)
        warped = split_alpha(*warp_with_st_map(image, st, job.filter, job.samples, job.antialias, progress=progress,
                                               alpha_channel=named, looked=plan, into=into), alpha=named)
        del into, st
        if not job.keep_maps:  # one still image: the map goes before its output is written
            _CACHE.pop(("stmap", os.path.abspath(job.stmap)), None)
    else:
        src = source_camera(job.source, meta, image.shape)
        image, src = stored_frame(image, meta, src)
        true_src = src
        if job.flip or job.source_flip:
            from lenslab.warp.mirror import mirror_frames, mirror_source_pose, parse_flips

            image = mirror_frames(image, src.lens, parse_flips(job.source_flip, "hv", "--source-flip"))
            src = mirror_source_pose(src, parse_flips(job.flip))
        size = job.size or default_output_size(job.to, src.lens)
        src = place_source(job.to, src, records_place(src, meta), job.eye)
        dst = output_camera(job, src, size)
        if job.autoscale:
            dst = autoscale_camera(src, dst, job.autoscale, job.samples, job.quiet, job.verbose)
        if hasattr(progress, "status"):
            progress.status("making the map")
        plan = cache.plan(src, dst)
        if hasattr(progress, "start"):  # a bar over the plan's bands (lenslab.jobs.progress), each counted as drawn
            from lenslab.warp.tiles import band_count

            progress.start(band_count(plan), unit="band")
        from lenslab.jobs.warp.output import output_arrays

        source_alpha = carries_alpha(meta, image.shape[2])  # (the output's memory ready to take its alpha)
        into = output_arrays(plan.out_shape, image.shape[2], fmt, job, meta, source_alpha)
        warped = cache.warp_frame(image, src, dst, progress=progress, into=into,  # as every video frame is
                                  alpha=source_alpha, plan=plan)
        del into
    if job.antialias:
        from lenslab.jobs.warp.output import note_softening

        note_softening(job, plan)
    del image  # (the source is not kept while the output is developed and written)
    from lenslab.jobs.warp.output import write_warped

    warped = list(warped)  # handed over: no array of the output's size kept here while it is written
    if hasattr(progress, "status"):  # a large output takes longer to write than to warp: the full bar says so
        progress.status(f"writing {Path(dst_path).name}")
    if not job.stmap:  # the view the pixels show: a mirrored one recorded as mirrored
        from lenslab.warp.mirror import shown_camera

        dst = shown_camera(true_src, src, dst)
    write_warped(dst_path, warped.pop(0), warped.pop(0), meta, fmt, job, dst, source_alpha, given_up=True)


def _other_views(src_path: str, meta: dict, target: str = "") -> tuple[list[str], str, str]:
    """The channels of a multi-view EXR's other views, beside the default view a warp reads without a selector
    (``left.R``... of a stereo file): the names, the output's title and why they are not written (another view's
    colour, warped from its own name, not data of this view's camera)."""
    views = [str(v) for v in (meta.get("attributes") or {}).get("multiView") or []]
    if not views or meta.get("view") is not None:
        return [], target, ""
    from lenslab.io.exr.select import view_of

    names = [n for n in meta.get("extra_channels") or [] if view_of(n, views) != views[0]]
    rest = sorted({view_of(n, views) for n in names})
    from lenslab.io import split_selector

    name = Path(split_selector(str(src_path))[0]).name
    return names, target, (f"they belong to the other view(s) {', '.join(rest)} (the file's default view, "
                           f"{views[0]}, is warped); warp a view by its name, e.g. {name}:{rest[0] if rest else ''}")


def plans_for(job: WarpJob):
    """This process's :class:`~lenslab.warp.batch.PlanCache` for the sampling of ``job`` (made on first
    use; one batch's maps at a time)."""
    key = ("plans", job.batch, job.compat, job.filter, job.samples, job.antialias, job.seed, job.allow_parallax, job.exact_map)
    with _CACHE_LOCK:
        if key not in _CACHE:
            for old in [k for k in _CACHE if k[0] == "plans"]:
                del _CACHE[old]
            _CACHE[key] = plan_cache(job)
        return _CACHE[key]


def plan_cache(job):
    """The plans (maps) of this job's warps, one per geometry, made once and reused."""
    from lenslab.warp import WarpPlan
    from lenslab.warp.batch import PlanCache

    factory = WarpPlan
    if job.compat == "v360":
        from lenslab.warp.compat_v360 import V360Plan as factory
    from lenslab.warp.batch import MAX_MAP_BYTES

    # maps not kept: each band's lives in scratch memory while it is drawn, in bands of SCRATCH_POINTS
    kept = {} if job.keep_maps else {"max_map_bytes": 0, "band_points": SCRATCH_POINTS}
    return PlanCache(factory=factory, filter=job.filter, samples=job.samples, antialias=job.antialias,
                     seed=job.seed, allow_parallax=job.allow_parallax, exact_map=job.exact_map, **kept)


#: output samples per band of a warp whose maps are not kept: a band's map and scratch stay a few MB per
#: thread (as fast as the engine's larger bands: the kernels' work per sample dominates)
SCRATCH_POINTS = 1 << 16


def st_map(path: str):
    """The ST map at ``path`` (its s and t, :func:`lenslab.stmap_rows.packed`: half the memory of the image it is
    read as) and the source spec and size its mark records (or None), read once per process."""
    key = ("stmap", os.path.abspath(path))
    if key not in _CACHE:
        from lenslab.stmap import read_st_map
        from lenslab.stmap_rows import packed

        st, recorded = read_st_map(path, source=True)
        _CACHE[key] = packed(st), recorded
    return _CACHE[key]


__all__ = ["WarpJob", "warp_one", "plans_for", "plan_cache", "st_map"]
