"""The one batch runner: jobs on workers, kept in a results file — how ``ekm compare`` and ``ekm tournament`` run
their runs and games (docs/design.md §5).

A :class:`Batch` says what a command's jobs are called and how each is keyed, named and failed;
:func:`run_batch` sends the jobs to a worker pool (:mod:`evaluation.workers`: this process, local processes or a
Dask cluster) through :func:`run_jobs`, appends each finished job to the results file (:mod:`evaluation.results`)
as it arrives, runs none of a resumed file's jobs again, counts the jobs and the failed ones on a progress bar,
and on Ctrl-C stops the workers and says in one line what the file keeps and how to finish it. A job is a pure
function of its plain values, so the records do not depend on where or in what order the jobs ran.
"""

from __future__ import annotations

import sys
from dataclasses import dataclass
from typing import Callable

from ekm.errors import InputError, Interrupted

#: A job whose worker died is tried this many more times (on a fresh worker) before it is recorded as failed.
RETRIES = 3


@dataclass(frozen=True)
class Batch:
    """How a command names its batch and its jobs: ``noun`` ("comparison"), ``unit`` ("run"), the progress bar's
    ``verb`` ("comparing"); ``job_key(job)`` and ``record_key(record)``: a job's place in the results file, the
    same for a job and its record; ``identity(job)``: the job as its results-file line names it;
    ``failed(job, reason)``: the record of a job that could not be made (it raised in the pool, or its worker
    kept dying)."""

    noun: str
    unit: str
    verb: str
    job_key: Callable
    record_key: Callable
    identity: Callable
    failed: Callable


def run_batch(batch: Batch, job_list: list, pool, settings: dict, *, out=None, resume=None,
              progress: bool = False) -> list[dict]:
    """Every record of ``job_list`` run on ``pool``, in the jobs' order; ``out`` (a new results file) or
    ``resume`` (an earlier one with the same ``settings``, its jobs kept) receives each as it finishes. The pool
    is closed on return.

    Raises :class:`InputError` for a bad results file before any job runs, :class:`Interrupted` on Ctrl-C — with
    a results file, whenever the signal came: the console script holds signals until the file exists."""
    try:
        return kept(batch, job_list, settings, lambda done, on_done: run_jobs(job_list, pool, batch.failed, on_done,
                                                                             done=done),
                    out=out, resume=resume, progress=progress, stop=pool.stop)
    finally:
        pool.close()


def kept(batch: Batch, job_list: list, settings: dict, run, *, out=None, resume=None, progress: bool = False,
         stop=lambda: None) -> list[dict]:
    """:func:`run_batch`'s shell around any way of running the jobs: ``run(done, on_done)`` makes the records of
    ``job_list`` but those in ``done`` (``{index: record}``, kept from a resumed file), calls ``on_done(index,
    record)`` as each finishes and returns them all in the jobs' order; here each goes to the results file and the
    progress bar as it arrives. On Ctrl-C, ``stop()`` and :class:`Interrupted` with what the file keeps."""
    from ekm import interrupts

    store = None
    try:
        store = results_file(out, resume, settings, batch.record_key)
        interrupts.release()  # a signal the command line held until the file existed raises now (ekm.interrupts)
        done = {}
        if store is not None:
            index = {batch.job_key(j): i for i, j in enumerate(job_list)}
            done = {index[k]: r for k, r in store.done.items() if k in index}
        with Progress(len(job_list), done, progress, batch.unit, batch.verb) as bar:
            def on_done(i, record):
                if store is not None:
                    store.append(batch.identity(job_list[i]), record)
                bar.update(record)

            return run(done, on_done)
    except KeyboardInterrupt:
        try:
            stop()
        except KeyboardInterrupt:  # a second Ctrl-C while the workers stop: they are stopping
            pass
        raise Interrupted(stopped(batch, store, len(job_list))) from None
    finally:
        if store is not None:
            store.close()


def run_jobs(job_list: list, workers, failed, on_done=None, *, done: dict | None = None,
             retries: int = RETRIES) -> list[dict]:
    """Run ``job_list`` on ``workers`` and return their records in the jobs' order, whatever order they finished in.

    ``done``: ``{index: record}`` of jobs already made (a resumed batch): not run again. ``on_done(index, record)``
    is called for each job as it finishes (the results file, progress bars). A job whose worker dies is run again
    on a fresh worker up to ``retries`` times, then recorded as ``failed(job, reason)``, as is a job whose future
    raised (the workers' own run functions record their jobs' errors). Ctrl-C (:mod:`ekm.interrupts`) raises
    KeyboardInterrupt here, between results; the caller stops the workers.
    """
    from collections import deque
    from concurrent.futures import FIRST_COMPLETED, Future, wait

    from ekm import interrupts

    records: list = [None] * len(job_list)
    for i, record in (done or {}).items():
        records[i] = record
    queue = deque(i for i in range(len(job_list)) if records[i] is None)
    attempts = [0] * len(job_list)
    flying: dict = {}

    def finish(i: int, record: dict) -> None:
        # one copy of each repeated string (world, architecture, label, ending) however many jobs arrive
        records[i] = {k: sys.intern(v) if isinstance(v, str) and k != "failed" else v for k, v in record.items()}
        if on_done:
            on_done(i, record)

    def settle(i: int, future) -> bool:
        """Take a finished future's record, or put its job back in the queue; True if its worker died."""
        exc = future.exception()
        if exc is None:
            finish(i, future.result())
            return False
        if not workers.lost(exc):
            finish(i, failed(job_list[i], f"{type(exc).__name__}: {exc}".splitlines()[0]))
            return False
        attempts[i] += 1
        if attempts[i] <= retries:
            queue.appendleft(i)
        else:
            finish(i, failed(job_list[i], f"its worker died {attempts[i]} times ({type(exc).__name__})"))
        return True

    while queue or flying:
        interrupts.check()
        while queue and len(flying) < workers.window:
            i = queue.popleft()
            try:
                flying[workers.submit(job_list[i])] = i
            except Exception as exc:  # the pool broke while it started a worker
                if not workers.lost(exc):
                    raise
                broken = Future()
                broken.set_exception(exc)
                flying[broken] = i
                break
        finished, _ = wait(flying, timeout=0.5, return_when=FIRST_COMPLETED)
        lost = [settle(flying.pop(future), future) for future in finished]
        if any(lost) and workers.breaks_whole:
            # a local pool breaks with its worker: every job it had in flight fails too; take them, renew it
            for future in wait(flying).done:
                settle(flying.pop(future), future)
            workers.renew()
    return records


def results_file(out, resume, settings: dict, record_key):
    """The results file the jobs go to (``out``: new; ``resume``: an earlier one continued), or None."""
    from evaluation.results import ResultsFile

    if out is not None and resume is not None:
        raise InputError("--out and --resume: give one (--resume PATH appends to PATH)")
    if out is not None:
        return ResultsFile(out, settings, option="--out")
    if resume is not None:
        return ResultsFile(resume, settings, resume=True, key_of=record_key)
    return None


def stopped(batch: Batch, store, total: int) -> str:
    """The line of an interrupted batch: what was kept and how to go on."""
    if store is None:
        return (f"{batch.noun} stopped; no results file was written (--out RESULTS keeps every finished "
                f"{batch.unit})")
    kept = len(store.done) + store.appended
    return (f"{batch.noun} stopped; {kept} of {total} {batch.unit}s are in {store.path}; "
            f"run the same command with --resume {store.path} to finish it")


class Progress:
    """The progress bar of a batch (jobs done, failed, time left) on stderr, or nothing."""

    def __init__(self, total: int, done: dict, show: bool, unit: str, verb: str):
        self.bar = None
        self.failed = sum("failed" in r for r in done.values())
        if show:
            from tqdm import tqdm

            self.bar = tqdm(total=total, initial=len(done), unit=unit, desc=verb, dynamic_ncols=True)
            if self.failed:
                self.bar.set_postfix(failed=self.failed)

    def update(self, record: dict) -> None:
        if self.bar is None:
            return
        if "failed" in record:
            self.failed += 1
            self.bar.set_postfix(failed=self.failed, refresh=False)
        self.bar.update(1)

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        if self.bar is not None:
            self.bar.close()
