"""The one runner: any job over its (input, output) pairs, on threads of this process or on a Dask
cluster, with the same results: ``(input, output, error or None, notes)`` per pair, in the pairs' order.

On a cluster each task writes its outputs to temporaries named for this process and hands them back;
this process renames them as the results come in (:func:`lenslab.atomic.staged`). After Ctrl-C,
SIGTERM or a lost scheduler nothing is renamed any more, the tasks still running discard what they
write (they check the batch's stop event), and whatever they leave is named for a process that has
ended, so the next batch in that folder sweeps it.
"""

from __future__ import annotations

import os
import sys

from lenslab.jobs.job import Job


def execute(job: Job, src: str, dst: str, progress=None) -> tuple[str, str, str | None, list[str]]:
    """Run ``job`` on one file; a failure becomes this file's one-line error, warnings become its notes."""
    from lenslab.cluster.threads import recorded_warnings
    from lenslab.errors import stop_signal
    from lenslab.current_input import from_input
    from lenslab.jobs.funnel import one_line, user_notes

    with recorded_warnings() as caught, from_input(src):  # a note that counts files counts this one once
        try:
            job.run(src, dst, progress=progress)
            error = None
        except Exception as exc:  # noqa: BLE001 - one bad file must not stop the batch
            if stop_signal(exc) is not None:  # Ctrl-C that surfaced as another error: it stops the batch
                raise
            error = one_line(exc)
        finally:  # a clip this job probed and did not decode: its file closed now, not at the next probe
            opened = sys.modules.get("lenslab.io.video.opened")
            if opened is not None:
                opened.release()
    return src, dst, error, user_notes(caught)


def execute_staged(job: Job, src: str, dst: str, owner: str, stop: str) -> tuple:
    """What runs on a cluster worker: :func:`execute` with the outputs left as temporaries named for the
    process ``owner`` (the command), listed in the result's fifth item for it to rename. When the batch's
    stop event ``stop`` is set (or the scheduler cannot say), the temporaries are removed instead."""
    from contextlib import nullcontext

    from lenslab.staging import discard, staged
    from lenslab.cluster.tasks import limit_threads
    from lenslab.cluster.threads import routed_warnings

    limit_threads()
    with staged(owner) as written, routed_warnings() if _worker_threads() > 1 else nullcontext():
        result = execute(job, src, dst)  # (a worker of several threads runs several files at once: notes by thread)
    if written and _stopped(stop):
        discard(written)
        return src, dst, "not written: the command was stopped", [], []
    if "lenslab.tone.repairs" in sys.modules:  # slight negatives: the command sums them in its one line
        from lenslab.tone.repairs import take_note

        result = (*result[:3], result[3] + [n for n in (take_note(),) if n])
    return (*result, list(written))


def _worker_threads() -> int:
    """The tasks the Dask worker running this one runs at once (1 where no worker can say)."""
    try:
        from distributed import get_worker

        return int(get_worker().state.nthreads)
    except Exception:  # noqa: BLE001 - not on a worker
        return 1


def _stopped(name: str) -> bool:
    try:
        from distributed import Event

        return bool(Event(name).is_set())
    except Exception:  # noqa: BLE001 - no scheduler to ask: the command is gone too
        return True


def run_local(job: Job, pairs: list[tuple], jobs: int = 0, progress: bool = False) -> list[tuple]:
    """Run ``job`` on every pair, ``jobs`` files at once on threads of this process (0: one per core, as
    many as the memory holds judging by the first file). ``progress``: a bar by files, or by rows of the
    image when there is one file (a clip's own, by frames, when it is a clip)."""
    from lenslab.cluster.threads import default_jobs, run_threads

    one = len(pairs) == 1
    bar = None
    if progress and not one:  # one file has its bar of rows; tqdm is imported only for a bar
        from tqdm import tqdm

        bar = tqdm(total=len(pairs), unit="img", file=sys.stderr, leave=False)

    def work(pair):
        from lenslab.jobs.progress import RowBar
        from lenslab.jobs.warp.video import is_video

        # one image: a bar of its rows or bands; a clip has its own bar, by frames
        rows = RowBar(os.path.basename(str(pair[0]))) if progress and one and not is_video(pair[0]) else None
        try:
            return execute(job, pair[0], str(pair[1]), progress=rows)
        finally:
            if rows is not None:
                rows.close()

    try:
        # the first file alone, on every core: it makes what the others share (a warp's map)
        return run_threads(work, pairs, jobs or default_jobs(max(1, len(pairs) - 1)),
                           None if bar is None else lambda _: bar.update(), first_alone=True, fit_memory=not jobs)
    finally:
        if bar is not None:
            bar.close()


def connect(args):
    """The client to the scheduler the options name (``--scheduler``, ``--scheduler-file``,
    ``DASK_SCHEDULER_ADDRESS``), connected now, or None: run on this machine.

    A batch calls this before it makes any folder: a scheduler that cannot be reached or does not answer
    within ``--scheduler-timeout`` is an :class:`OSError` naming its address, and the batch has made
    nothing. :func:`run_on_cluster` closes the client."""
    from lenslab.cluster.connect import open_client, scheduler_address

    where = scheduler_address(args)
    return None if where is None else open_client(where, getattr(args, "scheduler_timeout", None))


def run_on_cluster(client, job: Job, pairs: list[tuple], progress: bool = False,
                   workers: dict | None = None, close: bool = True) -> list[tuple]:
    """Run ``job`` on every pair on the cluster of ``client`` (closed here unless ``close`` is False), one
    task per file; the outputs are renamed here as their tasks report. ``workers`` receives per-worker
    ``[files, seconds]``.

    A lost scheduler is a :class:`~lenslab.cluster.run.SchedulerLost` that counts what was done."""
    import secrets

    from lenslab.atomic import owner, temporaries
    from lenslab.staging import commit, discard
    from lenslab.cluster.connect import close_client
    from lenslab.cluster.run import SchedulerLost, gather_as_completed, submit_many
    from lenslab.jobs.funnel import one_line
    from lenslab.jobs.policy import check_output

    # Outputs are checked here, once, before any task runs; each task's output is renamed here.
    refused, ready = {}, []
    for src, dst in pairs:
        try:
            check_output(dst, [src], job.overwrite)
            ready.append((src, dst))
        except OSError as exc:
            refused[(str(src), str(dst))] = str(exc)
    stop = f"lenslab-stop-{secrets.token_hex(8)}"
    remote = job.for_workers()  # workers have their own working folder: absolute paths
    tasks = [(remote, os.path.abspath(src), os.path.abspath(dst), owner(), stop) for src, dst in ready]
    done: dict[int, tuple] = {}
    try:
        futures = submit_many(client, execute_staged, tasks, name=job.command)
        index = {f.key: i for i, f in enumerate(futures)}
        for fut, value, worker, seconds, error in gather_as_completed(client, futures, progress, desc=job.command):
            i = index[fut.key]
            src, dst = (str(p) for p in ready[i])
            notes: list = []
            if error is None:
                _, _, error, notes, written = value
                try:
                    if error is None:
                        commit(written)
                    else:
                        discard(written)
                except OSError as exc:
                    error = one_line(exc)
            done[i] = (src, dst, error and as_given(error, src), [as_given(n, src, dst) for n in notes])
            if workers is not None and error is None:
                w = workers.setdefault(worker, [0, 0.0])
                w[0] += 1
                w[1] += seconds
    except BaseException as exc:
        _set_stop(client, stop)
        if isinstance(exc, SchedulerLost):
            exc.done = sum(1 for r in done.values() if r[2] is None)
            exc.total = len(pairs)
        raise
    finally:
        for _, dst in ready:  # what lost workers (or a stopped batch) left: nobody will rename it now
            for tmp in temporaries(dst):
                tmp.unlink(missing_ok=True)
        if close:
            close_client(client)
    by_pair = {(r[0], r[1]): r for r in done.values()}
    return [by_pair.get((str(src), str(dst)), (str(src), str(dst), refused.get((str(src), str(dst))), []))
            for src, dst in pairs]


def as_given(text: str, *paths: str) -> str:
    """``text`` of a worker, which had the absolute ``paths``, naming them as the command was given them (as a run
    on this machine names them)."""
    for path in paths:
        text = text.replace(os.path.abspath(path), path)
    return text


def _set_stop(client, name: str) -> None:
    """Tell the tasks still running that their outputs are not wanted (best effort: within two seconds;
    a task that cannot ask the scheduler discards its outputs too)."""
    import threading

    def set_event():
        try:
            from distributed import Event

            Event(name, client=client).set()
        except Exception:  # noqa: BLE001 - no scheduler: the tasks cannot ask either, and discard
            pass

    t = threading.Thread(target=set_event, daemon=True)
    t.start()
    t.join(2.0)


def report_results(command: str, results: list[tuple], summary: str | None, total: int | None = None,
                   tail: str = "") -> list:
    """Print each ``(input, output, error, notes)`` result's notes and failure, then ``summary`` (None:
    none) with ``{done}`` and ``{total}`` (default: the results) filled in, the failures counted and
    ``tail`` added. A note on the whole command (:class:`~lenslab.jobs.funnel.CommandNote`) is printed once,
    with the first file that gave it, however many processes gave it. Returns the failed ones."""
    from lenslab.jobs.funnel import command_note, said

    told: set = set()
    given = None  # a worker's absolute paths -> the inputs as given, for the files of a worker's tally
    for src, _, _, notes in results:
        if notes:  # the tone package only for notes to absorb
            from lenslab.tone.repairs import absorb_note

            given = given or {os.path.abspath(str(r[0])): str(r[0]) for r in results}
        for note in notes:  # repaired values, clamped halves: reported, never hidden
            once = command_note(note)
            if said(note):  # printed once already, as the command read its options (a camera file's note)
                continue
            if once is None and absorb_note(note, given):  # a worker's slight negatives: in the command's one line
                continue
            if once is not None:
                if once in told:
                    continue
                told.add(once)
            print(f"{command}: note: {src}: {note if once is None else once}", file=sys.stderr)
    from lenslab.jobs.frame_files import names_output
    from lenslab.jobs.funnel import naming

    failed = [(src, err) for src, _, err, _ in results if err]
    for src, dst, err, _ in results:  # an error of the output (it exists, ...) names the output alone
        if err:
            print(f"{command}: error: {err if names_output(err, dst) else naming(src, err)}", file=sys.stderr)
    if summary is not None:
        print(summary.format(done=len(results) - len(failed), total=len(results) if total is None else total)
              + (f"; {len(failed)} failed" if failed else "") + tail, file=sys.stderr)
    return failed


def run_batch(command: str, job: Job, pairs: list[tuple], args, summary, skipped: int = 0) -> int:
    """The batch commands' common end: run ``job`` on ``pairs`` on the cluster of ``args._client`` (from
    :func:`connect`) or on this machine (``args.jobs`` files at once), print notes, failures and the
    summary, and return the exit status (1 if any failed).

    ``summary(where)``: the summary line with ``{done}`` and ``{total}`` to fill in, called after the
    run; ``where`` is ``" on the cluster at ADDRESS"`` or empty."""
    from lenslab.cluster.run import SchedulerLost, worker_summary

    quiet = getattr(args, "quiet", False)
    client = getattr(args, "_client", None)
    progress = not quiet and sys.stderr.isatty()
    workers: dict = {}
    where = ""
    if client is not None:
        where = f" on the cluster at {client.scheduler.address}"
        try:
            results = run_on_cluster(client, job, pairs, progress, workers)
        except SchedulerLost as exc:
            raise OSError(f"lost the Dask scheduler at {exc.address}: {exc.done + skipped} of "
                          f"{exc.total + skipped} output(s) are done; run again with --skip-existing for the "
                          "rest") from None
    else:
        results = run_local(job, pairs, getattr(args, "jobs", 0), progress)
    alone = len(results) == 1 and not skipped and results[0][2]  # one input that failed: its one line says all
    failed = report_results(command, results, None if quiet or alone else summary(where), total=len(results) + skipped,
                            tail=f"; {skipped} already there, left alone" if skipped else "")
    if not quiet:
        for line in worker_summary(workers):
            print(line, file=sys.stderr)
    return 1 if failed else 0


__all__ = ["execute", "execute_staged", "run_local", "run_on_cluster", "connect", "report_results", "run_batch"]
