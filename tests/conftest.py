"""Shared test set-up: how many xdist workers ``-n auto`` starts, one JAX compilation cache for every process of a
run, every test leaves the process's CPU affinity as it found it, the ``registries`` fixture puts back what a test
registered (robots.registry), and ``installed`` installs an example package of ``examples/`` as pip would.

``ekm run`` and ``ekm compare --workers 1`` pin their process to one CPU (:mod:`evaluation.pinning`); tests
call the CLI in the pytest process — an xdist worker, in the default run — and a pinned worker would hand one
CPU to every later test it runs and to the subprocesses and worker pools those start. Each worker restores the
CPUs it started with (those the whole run may use), so a pin lasts one test and never reaches another worker.
"""

import os
import shutil
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"

# One JAX compilation cache for the test processes and every process a test starts (the commands it runs, their
# worker pools): each would compile the same steps again, and a later run compiles none it has compiled before.
# It is kept in pytest's own cache directory, which git ignores; set JAX_COMPILATION_CACHE_DIR to keep it elsewhere.
# A compiled step is the same program whether compiled or read back, so no result depends on it.
os.environ.setdefault("JAX_COMPILATION_CACHE_DIR", str(ROOT / ".pytest_cache" / "jax"))
os.environ.setdefault("JAX_PERSISTENT_CACHE_MIN_COMPILE_TIME_SECS", "0")

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


@pytest.fixture
def registries():
    """Every registry (architectures, players, families, robots) as it was before the test, afterwards: what the test
    registered is gone, and the entry points are read again on next use."""
    import robots.controllers.spec  # noqa: F401  (each kind's registry is made when its module is imported)
    import robots.generator  # noqa: F401
    import robots.robotfile  # noqa: F401
    import robots.soccer.roster  # noqa: F401
    from robots.registry import KINDS

    saved = [(r, dict(r._added), set(r._from_entry_points), r._loaded) for r in KINDS]
    yield KINDS
    for r, added, from_entry_points, loaded in saved:
        r._added.clear()
        r._added.update(added)
        r._from_entry_points.clear()
        r._from_entry_points.update(from_entry_points)
        r._loaded = loaded


@pytest.fixture
def installed(tmp_path):
    """``installed(NAME)``: a directory that holds the example package ``examples/NAME`` as pip would install it —
    its module and a dist-info with its entry points (what importlib.metadata reads) — to put on the path."""

    def install(name: str) -> Path:
        project = tomllib.loads((EXAMPLES / name / "pyproject.toml").read_text())["project"]
        info = tmp_path / f"{project['name'].replace('-', '_')}-{project['version']}.dist-info"
        info.mkdir()
        info.joinpath("METADATA").write_text(f"Metadata-Version: 2.1\nName: {project['name']}\n"
                                             f"Version: {project['version']}\n")
        info.joinpath("entry_points.txt").write_text("".join(
            f"[{group}]\n" + "".join(f"{k} = {v}\n" for k, v in entries.items())
            for group, entries in project["entry-points"].items()))
        for module in (EXAMPLES / name).glob("*.py"):
            shutil.copy(module, tmp_path)
        return tmp_path

    return install
