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


#: A local pool whose workers all died before any of them started, this many pools in a row, stops the batch.
DEAD_AT_START = 2


class LocalPool:
    """``n`` spawned worker processes, made again when one dies — unless every worker of :data:`DEAD_AT_START`
    pools in a row died before it started (:meth:`renew`)."""

    def __init__(self, run, n: int):
        self.run, self.n = run, n
        self.window = n
        self.breaks_whole = True  # one dead worker breaks the pool: every run in flight fails with it
        self.where = f"{n} local workers"
        self._pool = None
        self._started = None  # how many of the pool's workers got through their start (the initializer's count)
        self._dead_at_start = 0

    def _new(self):
        import multiprocessing
        from concurrent.futures import ProcessPoolExecutor

        context = multiprocessing.get_context("spawn")
        self._started = context.Value("i", 0)
        return ProcessPoolExecutor(self.n, mp_context=context, initializer=_start_worker,
                                   initargs=(self._started,))

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
        """Drop the broken pool (and any of its processes still alive); the next run starts a new one.

        Raises :class:`InputError` (:func:`died_at_start`) when no worker of this pool nor of the one before
        started: every run would fail the same way, so the batch stops with the cause instead of a table of
        failed runs."""
        started = self._started is not None and self._started.value > 0
        self._dead_at_start = 0 if started else self._dead_at_start + 1
        self.stop()
        if self._dead_at_start >= DEAD_AT_START:
            raise InputError(died_at_start(self._dead_at_start))

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


def died_at_start(pools: int) -> str:
    """The one line of a batch whose local workers all died as they started, ``pools`` pools in a row: the
    script that runs the batch again in each worker it spawns (:func:`unguarded_script`), or what to look at."""
    script = unguarded_script()
    if script is not None:
        return (f"{script}: every worker process died as it started: a spawned worker imports the script, which "
                f"starts the work again; put the work in a function main() and end the script with the two lines "
                f"'if __name__ == \"__main__\":' and '    main()' (or run it with workers=1)")
    return (f"every worker process died as it started ({pools} pools in a row), before any run began; its error is "
            f"above on stderr (workers=1, --workers 1, runs in this process)")


def unguarded_script() -> str | None:
    """The path of the ``__main__`` script if the statement of it that is running now is outside an
    ``if __name__ == "__main__":`` block — so that a spawned worker, which imports the script under another
    name, runs that statement again — else None (no script: a notebook, ``python -c``, the console script)."""
    import ast
    import sys

    main = sys.modules.get("__main__")
    path = getattr(main, "__file__", None)
    frame = sys._getframe()
    while frame is not None and not (frame.f_globals is vars(main) and frame.f_code.co_name == "<module>"):
        frame = frame.f_back
    if path is None or frame is None:
        return None
    try:
        with open(path, encoding="utf-8") as f:
            tree = ast.parse(f.read())
    except (OSError, SyntaxError, ValueError):
        return None

    def is_main(test) -> bool:
        if not (isinstance(test, ast.Compare) and len(test.ops) == 1 and isinstance(test.ops[0], ast.Eq)):
            return False
        sides = [test.left, test.comparators[0]]
        return (any(isinstance(x, ast.Name) and x.id == "__name__" for x in sides)
                and any(isinstance(x, ast.Constant) and x.value == "__main__" for x in sides))

    line = frame.f_lineno
    guarded = any(isinstance(node, ast.If) and is_main(node.test) and node.lineno <= line <= node.end_lineno
                  for node in ast.walk(tree))
    return None if guarded else path


def spawning() -> bool:
    """True in a spawned worker that is still starting: it imports the parent's ``__main__`` script, and a
    statement of the script outside ``if __name__ == "__main__":`` is asking for workers again."""
    from multiprocessing import process

    return bool(getattr(process.current_process(), "_inheriting", False))


def workers_for(run, workers: int | None, scheduler: str | None):
    """The workers a comparison's runs go to: a Dask cluster's (``scheduler``), this process (``workers`` 1)
    or a local pool (default: one worker per core).

    In a spawned worker that is still starting (:func:`spawning`: its parent's script has no ``__main__``
    guard) the worker leaves at once, quietly — the parent names the cause (:func:`died_at_start`) rather than
    each worker printing a traceback."""
    if spawning():
        raise SystemExit(3)
    if scheduler:
        return DaskWorkers(run, scheduler)
    workers = workers or os.cpu_count() or 1
    return InProcess(run) if workers == 1 else LocalPool(run, workers)
