"""``lenslab tonemap`` of many inputs: files, folders and glob patterns into the folder ``-o``, one task
per file, on this machine or on a Dask cluster (``--scheduler``). One input with ``-o FILE`` stays with
:func:`lenslab.cli.tonemap.run`."""

from __future__ import annotations

import argparse
import glob
import os
import sys
from pathlib import Path


def is_batch(args: argparse.Namespace) -> bool:
    """Many inputs, a folder or a pattern, an output folder, or a cluster: the batch path."""
    from lenslab.cluster import scheduler_address

    first = args.inputs[0]
    out = Path(args.output)
    return (len(args.inputs) > 1 or os.path.isdir(first) or (glob.has_magic(first) and not os.path.exists(first))
            or out.is_dir() or out.suffix == "" or scheduler_address(args) is not None)


def run_many(args: argparse.Namespace, curve: str, params: dict, target=None) -> int:
    """Tone-map every input into the folder ``-o`` (or the one file ``-o`` names); exit code 1 if any failed.
    ``target``: the output format record whose channels each input must fit (None: no check, a display's
    codes are RGB whatever the input), checked once the outputs are planned, before any image is read."""
    from lenslab.cli.display import display_options
    from lenslab.io.registry import get
    from lenslab.jobs.arguments import parse_exposure
    from lenslab.jobs.plan import expand_inputs, plan_outputs, skip_existing, sweep_outputs
    from lenslab.jobs.policy import make_output_dir
    from lenslab.jobs.runner import connect, run_batch
    from lenslab.jobs.tonemap import TonemapJob

    exposure = parse_exposure(args.exposure)
    roots: dict[str, str] = {}
    files, missing = expand_inputs(args.inputs, False, roots)
    from lenslab.jobs.funnel import report_missing

    report_missing("lenslab tonemap", missing)
    if not files:
        if not missing:  # each missing input already has its line
            print("lenslab tonemap: error: nothing to tone-map", file=sys.stderr)
        return 1
    pairs = plan_outputs(files, args.output, get(args.format or "png").extensions[0], roots, verb="tone-map")
    if target is not None:
        from lenslab.jobs.stages import check_channels_fit

        for src, _ in pairs:
            check_channels_fit(src, target)
    job = TonemapJob.from_options(args, curve=curve, params=params, exposure=exposure, **display_options(args))
    args._client = connect(args)  # an unreachable scheduler: one error, before any folder is made
    if len(pairs) > 1 or Path(args.output).suffix == "" or Path(args.output).is_dir():
        make_output_dir(args.output)
        for folder in sorted({Path(dst).parent for _, dst in pairs}):
            folder.mkdir(parents=True, exist_ok=True)  # the sub-folders a pattern's matches mirror
    sweep_outputs(pairs)  # temporaries of killed runs
    pairs, skipped = skip_existing(pairs, args.skip_existing)
    status = run_batch("lenslab tonemap", job, pairs, args, lambda where: f"tone-mapped {{done}} of {{total}} file(s){where}",
                       skipped)
    if not status or len(pairs) > 1:  # something was written through the display: its view, once
        from lenslab.cli.display import say_view

        say_view(args.output, display_options(args), args.quiet)
    return 1 if status or missing else 0


__all__ = ["is_batch", "run_many"]
