"""Where a comparison's runs go: this process, local worker processes, or a Dask cluster (imperative shell).

All three offer the same small interface to :func:`evaluation.compare.compare`: ``submit(job)`` returns a
:class:`concurrent.futures.Future` of the run's record; ``window`` is how many runs to keep in flight;
``lost(exc)`` says whether a run's exception means its worker died (the out-of-memory killer, a signal, a
crash), so that the run is tried again; ``breaks_whole`` whether such a death fails every run in flight;
``renew()`` replaces what died; ``stop()`` ends every worker at once
(Ctrl-C) and ``close()`` ends them when the work is done.

Local workers are spawned processes (a forked JAX process can deadlock), each pinned to a CPU of its own
(:mod:`evaluation.pinning`) and deaf to Ctrl-C, which the parent handles. When one dies the standard pool
is broken for good — every run in flight fails with ``BrokenProcessPool`` — so the pool is made again and
those runs are submitted again. Keeping no more runs in flight than there are workers means that the runs
a broken pool takes down are exactly those that were running.
"""

from __future__ import annotations

import os
from concurrent.futures import Future

from ekm.errors import InputError


def _start_worker(counter) -> None:
    """Initializer of a local worker: a CPU of its own, and Ctrl-C left to the parent."""
    from ekm.interrupts import ignore_in_worker
    from evaluation.pinning import pin_worker

    ignore_in_worker()
    pin_worker(counter)


class InProcess:
    """One worker: the runs go in this process, one at a time (the same runs: each is a pure function of
    its job)."""

    window = 1
    breaks_whole = False

    def __init__(self, run):
        self.run = run
        self.where = "1 local worker (this process)"

    def submit(self, job) -> Future:
        future = Future()
        try:
            future.set_result(self.run(job))
        except Exception as exc:  # Ctrl-C (KeyboardInterrupt) goes on up
            future.set_exception(exc)
        return future

    def lost(self, exc: BaseException) -> bool:
        return False

    def renew(self) -> None:
        pass

    def stop(self) -> None:
        pass

    def close(self) -> None:
        pass


class LocalPool:
    """``n`` spawned worker processes, made again when one dies."""

    def __init__(self, run, n: int):
        self.run, self.n = run, n
        self.window = n
        self.breaks_whole = True  # one dead worker breaks the pool: every run in flight fails with it
        self.where = f"{n} local workers"
        self._pool = None

    def _new(self):
        import multiprocessing
        from concurrent.futures import ProcessPoolExecutor

        context = multiprocessing.get_context("spawn")
        return ProcessPoolExecutor(self.n, mp_context=context, initializer=_start_worker,
                                   initargs=(context.Value("i", 0),))

    def submit(self, job) -> Future:
        if self._pool is None:
            self._pool = self._new()
        return self._pool.submit(self.run, job)

    def lost(self, exc: BaseException) -> bool:
        """A broken pool, or one whose pipes closed while it started a worker (a run's own errors never get
        here: :func:`evaluation.compare.run_job` records them)."""
        from concurrent.futures.process import BrokenProcessPool

        return isinstance(exc, (BrokenProcessPool, OSError))

    def renew(self) -> None:
        """Drop the broken pool (and any of its processes still alive); the next run starts a new one."""
        self.stop()

    def stop(self) -> None:
        """End every worker now: their runs in flight are lost, nothing else is."""
        if self._pool is None:
            return
        # ProcessPoolExecutor can only wait for its workers or leave them; terminate them (its own list).
        for process in list(getattr(self._pool, "_processes", {}).values()):
            if process.is_alive():
                process.terminate()
        self._pool.shutdown(wait=True, cancel_futures=True)
        self._pool = None

    def close(self) -> None:
        if self._pool is not None:
            self._pool.shutdown(wait=True)
            self._pool = None


class DaskWorkers:
    """The workers of a running Dask scheduler. Dask runs again on another worker the tasks of a worker it
    loses (``distributed.scheduler.allowed-failures`` times) before it gives up with ``KilledWorker``; that
    too counts as a lost worker here."""

    def __init__(self, run, address: str):
        try:
            from distributed import Client
        except ImportError:
            raise InputError("--scheduler: Dask is not installed; pip install 'ekm[cluster]'") from None
        try:
            self.client = Client(address, timeout="10s")
        except (OSError, TimeoutError, ValueError) as exc:
            raise InputError(f"--scheduler {address}: cannot connect ({exc.__class__.__name__}: {exc})") from None
        self.run = run
        self.executor = self.client.get_executor(pure=False)
        threads = sum(self.client.nthreads().values()) or 1
        self.breaks_whole = False  # a lost worker costs its own runs only
        self.window = 4 * threads  # the scheduler keeps every worker busy; runs beyond that wait here
        self.where = f"Dask at {address}"

    def submit(self, job) -> Future:
        return self.executor.submit(self.run, job)

    def lost(self, exc: BaseException) -> bool:
        from distributed.scheduler import KilledWorker

        return isinstance(exc, KilledWorker)

    def renew(self) -> None:
        pass

    def stop(self) -> None:
        self.executor.shutdown(wait=False)
        self.client.close()

    def close(self) -> None:
        self.client.close()


def workers_for(run, workers: int | None, scheduler: str | None):
    """The workers a comparison's runs go to: a Dask cluster's (``scheduler``), this process (``workers`` 1)
    or a local pool (default: one worker per core)."""
    if scheduler:
        return DaskWorkers(run, scheduler)
    workers = workers or os.cpu_count() or 1
    return InProcess(run) if workers == 1 else LocalPool(run, workers)
