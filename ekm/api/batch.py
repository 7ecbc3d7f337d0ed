"""A batch of jobs on workers, kept in a results file: what ``ekm compare`` and ``ekm tournament`` share.

The jobs go to :func:`evaluation.compare.compare` on a worker pool (:mod:`evaluation.workers`); each finished
job is appended to the results file (:mod:`evaluation.results`) as it arrives, a resumed file's jobs are not run
again, a progress bar counts the jobs and the failed ones, and Ctrl-C stops the workers and says in one line
what the file keeps and how to finish it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from ekm.errors import InputError, Interrupted


@dataclass(frozen=True)
class Batch:
    """How a command names its batch and its jobs: ``noun`` ("comparison"), ``unit`` ("run"), the progress bar's
    ``verb`` ("comparing"); ``job_key(job)`` and ``record_key(record)``: a job's place in the results file, the
    same for a job and its record (None: :func:`evaluation.results.key` of a comparison's run);
    ``identity(job)``: the job as its results-file line names it."""

    noun: str
    unit: str
    verb: str
    job_key: Callable
    identity: Callable
    record_key: Callable | None = None


def run_batch(batch: Batch, job_list: list, pool, settings: dict, *, out=None, resume=None, progress: bool = False,
              failed=None) -> list[dict]:
    """Every record of ``job_list`` run on ``pool``, in the jobs' order; ``out`` (a new results file) or
    ``resume`` (an earlier one with the same ``settings``, its jobs kept) receives each as it finishes.
    ``failed``: as :func:`evaluation.compare.compare`. The pool is closed on return.

    Raises :class:`InputError` for a bad results file before any job runs, :class:`Interrupted` on Ctrl-C."""
    from evaluation.compare import compare as run_all

    store = None
    try:
        store = results_file(out, resume, settings, batch.record_key)
        done = {}
        if store is not None:
            index = {batch.job_key(j): i for i, j in enumerate(job_list)}
            done = {index[k]: r for k, r in store.done.items() if k in index}
        with Progress(len(job_list), done, progress, batch.unit, batch.verb) as bar:
            def on_done(i, record):
                if store is not None:
                    store.append(batch.identity(job_list[i]), record)
                bar.update(record)

            return run_all(job_list, pool, on_done, done=done, failed=failed)
    except KeyboardInterrupt:
        try:
            pool.stop()
        except KeyboardInterrupt:  # a second Ctrl-C while the workers stop: they are stopping
            pass
        raise Interrupted(stopped(batch, store, len(job_list))) from None
    finally:
        if store is not None:
            store.close()
        pool.close()


def results_file(out, resume, settings: dict, record_key=None):
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
