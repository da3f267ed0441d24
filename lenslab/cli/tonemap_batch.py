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


def run_many(args: argparse.Namespace, curve: str, params: dict) -> int:
    """Tone-map every input into the folder ``-o`` (or the one file ``-o`` names); exit code 1 if any failed."""
    from lenslab.cli.convert import expand_inputs, plan_outputs
    from lenslab.cli.options import parse_exposure
    from lenslab.cli.display import display_options
    from lenslab.cli.policy import make_output_dir
    from lenslab.cluster.command import batch_on_cluster, connect, report_results
    from lenslab.cluster.run import skip_existing
    from lenslab.cluster.tasks import tonemap_task

    exposure = parse_exposure(args.exposure)
    roots: dict[str, str] = {}
    files, missing = expand_inputs(args.inputs, False, roots)
    for pat, reason in missing:
        print(f"lenslab tonemap: {pat}: {reason}", file=sys.stderr)
    if not files:
        print("lenslab tonemap: error: nothing to tone-map", file=sys.stderr)
        return 1
    pairs = plan_outputs(files, args.format, args.output, roots)
    client = connect(args)  # an unreachable scheduler: one error, before any folder is made
    if len(pairs) > 1 or Path(args.output).suffix == "" or Path(args.output).is_dir():
        make_output_dir(args.output)
        for folder in sorted({Path(dst).parent for _, dst in pairs}):
            folder.mkdir(parents=True, exist_ok=True)  # the sub-folders a pattern's matches mirror
    pairs, skipped = skip_existing(pairs, args.skip_existing)
    if skipped and not args.quiet:
        print(f"lenslab tonemap: {skipped} output(s) already there, left alone (--skip-existing)", file=sys.stderr)
    options = {"curve": curve, "params": params, "exposure": exposure, "mode": args.mode,
               "primaries": args.primaries, "dither": args.dither, "bits": args.bits, "overwrite": args.overwrite,
               **display_options(args)}
    if client is not None:
        status = batch_on_cluster("lenslab tonemap", client, "tonemap_task", pairs, options, args.quiet, "tone-mapped")
        return 1 if status or missing else 0
    from tqdm import tqdm

    from lenslab.cluster.threads import default_jobs, run_threads

    with tqdm(total=len(pairs), unit="img", file=sys.stderr, leave=False,
              disable=args.quiet or not sys.stderr.isatty()) as bar:
        results = run_threads(lambda pair: tonemap_task(pair[0], str(pair[1]), options), pairs,
                              args.jobs or default_jobs(len(pairs)), lambda _: bar.update(), first_alone=True,
                              fit_memory=not args.jobs)
    failed = report_results("lenslab tonemap", results, None if args.quiet else "tone-mapped {done} of " + str(len(pairs) + skipped) + " file(s)"
                            + (f"; {skipped} already there, left alone" if skipped else ""))
    return 1 if failed or missing else 0


__all__ = ["is_batch", "run_many"]
