"""The batch commands' cluster path: connect, run one task per file, report as a local run does."""

from __future__ import annotations

import os
import sys


def connect(args):
    """The client to the scheduler the options name (``--scheduler``, ``--scheduler-file``,
    ``DASK_SCHEDULER_ADDRESS``), connected now, or None: run on this machine.

    A batch calls this before it makes any folder: a scheduler that cannot be reached is an
    :class:`OSError` naming its address, and the batch has made nothing. :func:`batch_on_cluster`
    closes the client."""
    from lenslab.cluster.connect import open_client, scheduler_address

    where = scheduler_address(args)
    return None if where is None else open_client(where)


def batch_on_cluster(command: str, client, task: str, pairs: list[tuple], options: dict,
                     quiet: bool = False, verb: str = "processed") -> int:
    """Run ``lenslab.cluster.tasks.<task>(input, output, options)`` for every pair on the cluster of
    ``client`` (from :func:`connect`, closed here); print each note and failure, a summary and what each
    worker did. Returns 1 if any failed."""
    from lenslab.cluster import tasks
    from lenslab.cluster.connect import close_client
    from lenslab.cluster.run import run_batch, worker_summary

    from lenslab.cli.policy import check_output

    fn = getattr(tasks, task)
    workers: dict = {}
    # Outputs are checked here, once, before any task runs. A task may run twice (its worker died after
    # writing the file but before the scheduler heard of it): the second run finds the first one's
    # complete output and replaces it with the same bytes, so the tasks may overwrite.
    refused, ready = {}, []
    for src, dst in pairs:
        try:
            check_output(dst, [src], options.get("overwrite", False))
            ready.append((src, dst))
        except OSError as exc:
            refused[(str(src), str(dst))] = str(exc)
    rerunnable = {**options, "overwrite": True}
    # workers have their own working folder: they get absolute paths, the messages keep the user's
    jobs = [(os.path.abspath(src), os.path.abspath(dst), rerunnable) for src, dst in ready]
    try:
        done = run_batch(client, fn, jobs, [dst for _, dst in ready], name=command.split()[-1],
                         progress=not quiet, workers=workers)
        address = client.scheduler.address
    finally:
        close_client(client)
    by_pair = {(str(src), str(dst)): (err and err.replace(os.path.abspath(src), str(src)), notes)
               for (src, dst), (_, _, err, notes) in zip(ready, done)}
    results = [(str(src), str(dst), *by_pair.get((str(src), str(dst)), (refused.get((str(src), str(dst))), [])))
               for src, dst in pairs]
    failed = report_results(command, results, None if quiet else
                            f"{verb} {{done}} of {{total}} file(s) on the cluster at {address}")
    if not quiet:
        for line in worker_summary(workers):
            print(line, file=sys.stderr)
    return 1 if failed else 0


def report_results(command: str, results: list[tuple], summary: str | None) -> list:
    """Print each ``(input, output, error, notes)`` result's notes and failure, then ``summary`` (None:
    none) with ``{done}`` and ``{total}`` filled in and the failures counted. Returns the failed ones."""
    from lenslab.tone.repairs import absorb_note

    for src, _, _, notes in results:
        for note in notes:  # repaired values, clamped halves: reported, never hidden
            if not absorb_note(note):  # a worker's slight negatives: in the command's one summary line
                print(f"{command}: note: {src}: {note}", file=sys.stderr)
    failed = [(src, err) for src, _, err, _ in results if err]
    for src, err in failed:
        print(f"{command}: FAILED: {err if src in err else f'{src}: {err}'}", file=sys.stderr)
    if summary is not None:
        print(summary.format(done=len(results) - len(failed), total=len(results))
              + (f"; {len(failed)} failed" if failed else ""), file=sys.stderr)
    return failed


__all__ = ["connect", "batch_on_cluster", "report_results"]
