"""What runs on a worker: one file per task, through the same functions as a local run.

A warp's map is made once per worker and per geometry, then reused for every later frame that worker
gets (:func:`worker_plans`): building it on the worker costs less than shipping it (see ``lenslab bench
cluster``), and a frame task carries only its file names and the options. Each task uses the threads
its worker was given (a Dask nanny sets ``OMP_NUM_THREADS``), so workers sharing a machine do not
fight over its cores.
"""

from __future__ import annotations

import argparse
import sys
import os

_PLANS: dict[tuple, object] = {}  # per worker process: warp options -> PlanCache


def worker_threads() -> int | None:
    """The worker's thread allowance (``OMP_NUM_THREADS``, set by the Dask nanny), else None (every core)."""
    try:
        return max(1, int(os.environ.get("OMP_NUM_THREADS", "")))
    except ValueError:
        return None


def limit_threads(n: int | None = None) -> None:
    """OpenCV, numba and the EXR codec use ``n`` threads (default: the worker's thread allowance)."""
    n = worker_threads() if n is None else n
    if n is None:
        return
    import cv2
    import numba

    import lenslab.io.exr

    cv2.setNumThreads(n)
    numba.set_num_threads(min(n, numba.config.NUMBA_NUM_THREADS))
    lenslab.io.exr.THREADS = 0 if n == 1 else n  # 0: the codec works in the calling thread, no pool


def worker_plans(options: dict):
    """This worker's :class:`~lenslab.warp.batch.PlanCache` for these warp options (made on first use)."""
    from lenslab.cli.warp_file import plan_cache

    key = ("plans",) + tuple(sorted((k, repr(v)) for k, v in options.items()))
    if key not in _PLANS:
        for old in [k for k in _PLANS if k[0] == "plans"]:  # one batch's maps at a time
            del _PLANS[old]
        _PLANS[key] = plan_cache(argparse.Namespace(**options))
    return _PLANS[key]


def guarded(src: str, dst: str, work) -> tuple[str, str, str | None, list[str]]:
    """Run ``work()``; a failure becomes this file's one-line error, warnings become its notes."""
    from lenslab.cli.policy import UsageError, one_line, user_notes
    from lenslab.errors import LenslabError

    from lenslab.cluster.threads import recorded_warnings

    with recorded_warnings() as caught:
        try:
            work()
            error = None
        except (LenslabError, OSError, UsageError) as exc:  # (an output that is a folder: a usage error)
            error = one_line(exc)
        except Exception as exc:  # one bad file must not stop the batch
            error = f"{type(exc).__name__}: {exc}"
    notes = user_notes(caught)
    if "lenslab.tone.repairs" in sys.modules:  # slight negatives: the command sums them in one line
        from lenslab.tone.repairs import take_note

        notes += [n for n in (take_note(),) if n]
    return src, dst, error, notes


def warp_task(src: str, dst: str, options: dict) -> tuple[str, str, str | None, list[str]]:
    """Warp one file as ``lenslab warp`` does (``options``: the command's options)."""
    from pathlib import Path

    from lenslab.cli.warp_file import warp_one

    limit_threads()
    args = argparse.Namespace(**options)

    def work():
        if args.stmap:  # read once per worker, not shipped with every frame
            args.st = worker_st_map(args.stmap)
        warp_one(src, Path(dst), args, worker_plans(options))

    return guarded(src, dst, work)


def worker_st_map(path: str):
    """The ST map at ``path``, read once per worker."""
    key = ("stmap", os.path.abspath(path))
    if key not in _PLANS:
        from lenslab.stmap import read_st_map

        _PLANS[key] = read_st_map(path)
    return _PLANS[key]


def convert_task(src: str, dst: str, options: dict) -> tuple[str, str, str | None, list[str]]:
    """Convert one file as ``lenslab convert`` does."""
    from lenslab.cli.convert_file import convert_one

    limit_threads()
    return guarded(src, dst, lambda: convert_one(src, dst, options))


def tonemap_task(src: str, dst: str, options: dict) -> tuple[str, str, str | None, list[str]]:
    """Tone-map one file as ``lenslab tonemap`` does."""
    from lenslab.cli.tonemap_file import tonemap_one

    limit_threads()
    return guarded(src, dst, lambda: tonemap_one(src, dst, options))


def plain_options(args: argparse.Namespace, paths: tuple[str, ...] = ()) -> dict:
    """A command's options as a dict a task can carry (the command's own module objects left out); the
    options named in ``paths`` that name an existing file become absolute (workers have their own
    working folder)."""
    options = {k: v for k, v in vars(args).items() if not k.startswith("_") and k != "st"}
    for key in paths:
        value = options.get(key)
        if isinstance(value, str) and os.path.exists(value):
            options[key] = os.path.abspath(value)
    return options


__all__ = ["warp_task", "convert_task", "tonemap_task", "worker_plans", "plain_options", "limit_threads"]
