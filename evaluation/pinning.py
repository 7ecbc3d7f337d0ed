"""One CPU per scenario process: what ``ekm compare``'s workers, ``ekm run`` and ``ekm compare --workers 1`` do.

A scenario run is one thread of Python (pymunk, the planner, the runner) calling one small jitted step per
0.128 s tick. Left free, the process moves between CPUs and XLA hands the step's kernels to a pool of
threads, one per CPU, that sleep between ticks; pinned to one CPU, the step runs on that CPU's caches
and the pool has one thread, so the controller's call is cheaper and whole runs are faster. Outcomes do
not depend on it: a run is a pure function of its job.

Pin before JAX creates its CPU backend (the first array), so that XLA sizes its thread pool for one CPU;
training (``ekm train``), which shares trials over CPU devices, is never pinned.
"""

from __future__ import annotations

import os


def pin_to_one_cpu(index: int = 0) -> int | None:
    """Restrict this process to the ``index``-th (modulo their number) of the CPUs it may use. Returns that CPU,
    or None where a process cannot be pinned (no ``os.sched_setaffinity``: macOS, Windows) or has one CPU."""
    if not hasattr(os, "sched_setaffinity"):
        return None
    cpus = sorted(os.sched_getaffinity(0))
    if len(cpus) < 2:
        return None
    cpu = cpus[index % len(cpus)]
    os.sched_setaffinity(0, {cpu})
    return cpu


def pin_worker(counter) -> None:
    """``ProcessPoolExecutor`` initializer: worker n (in start order, from the shared ``counter``) takes CPU n."""
    with counter.get_lock():
        index = counter.value
        counter.value += 1
    pin_to_one_cpu(index)
