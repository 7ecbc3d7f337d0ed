"""Shared test set-up: every test leaves the process's CPU affinity as it found it.

``ekm run`` and ``ekm compare --workers 1`` pin their process to one CPU (:mod:`evaluation.pinning`); tests
call the CLI in the pytest process, and a pinned pytest would hand one CPU to every later test and to the
subprocesses and worker pools those start.
"""

import os

import pytest


@pytest.fixture(autouse=True)
def _restore_cpu_affinity():
    cpus = os.sched_getaffinity(0) if hasattr(os, "sched_getaffinity") else None
    yield
    if cpus is not None and os.sched_getaffinity(0) != cpus:
        os.sched_setaffinity(0, cpus)
