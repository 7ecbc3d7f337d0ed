"""Shared test set-up: how many xdist workers ``-n auto`` starts, and every test leaves the process's CPU affinity
as it found it.

``ekm run`` and ``ekm compare --workers 1`` pin their process to one CPU (:mod:`evaluation.pinning`); tests
call the CLI in the pytest process — an xdist worker, in the default run — and a pinned worker would hand one
CPU to every later test it runs and to the subprocesses and worker pools those start. Each worker restores the
CPUs it started with (those the whole run may use), so a pin lasts one test and never reaches another worker.
"""

import os

import pytest

#: ``-n auto`` starts no more workers than this: each worker is a Python with JAX and pymunk loaded (a few hundred
#: MB) that compiles its own copies of the jitted code.
MAX_WORKERS = 8


def pytest_xdist_auto_num_workers(config):
    """``-n auto``: one worker per CPU this process may run on (its affinity, not the machine's count), at most
    :data:`MAX_WORKERS`."""
    cpus = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    return max(1, min(cpus, MAX_WORKERS))


@pytest.fixture(autouse=True)
def _restore_cpu_affinity():
    cpus = os.sched_getaffinity(0) if hasattr(os, "sched_getaffinity") else None
    yield
    if cpus is not None and os.sched_getaffinity(0) != cpus:
        os.sched_setaffinity(0, cpus)
