"""Mutation run for issue 12 item 5: mutmut 2.5.1's mutation operators, one mutant at a time, each in a fresh pytest.

mutmut 2.x rewrites the module on disk and starts a new Python per mutant, so no jitted JAX function keeps a
trace of the unmutated code (mutmut 3.x's in-process trampolines and forks would). This driver uses mutmut's own
mutation engine (mutmut.list_mutations / mutmut.mutate) and adds what `mutmut run` lacks here: a per-module test
list, a deterministic sample (every k-th mutant of each module, in mutmut's order) and one JSON line per mutant,
so the same mutant set can be run against two commits of the suite.

    python tests/mutation/run_mutants.py --root <clone> --every 8 --out results.jsonl
    python tests/mutation/run_mutants.py --root <clone> --out more.jsonl --ids ids.txt | --killed-in f | --survived-in f
    python tests/mutation/run_mutants.py --report after.jsonl [before.jsonl [rerun.jsonl]]

Run it from anywhere; the mutated clone is put first on PYTHONPATH and pytest runs from the clone's root. A
mutant is killed when pytest fails (or times out), survives when it passes. Only test files present in the clone
are run, so the clone at 3b8e0bf runs the suite without the known-answer files. Not collected by pytest.
"""

from __future__ import annotations

import argparse
import difflib
import importlib.util
import json
import os
import subprocess
import sys
import time
from pathlib import Path

from mutmut import Context, list_mutations, mutate

# the controller tests that drive the shipped EKM (split by controller module)
CONTROLLER_TESTS = ["robots/controllers/test_braitenberg.py", "robots/controllers/test_base.py",
                    "robots/controllers/test_fusion.py", "robots/controllers/test_fields.py",
                    "robots/controllers/test_memory.py", "robots/controllers/test_spec.py"]

# module -> the fast tests that exercise it (directly or through the code that calls it), as paths under tests/;
# known-answer tests first, so that a killed mutant usually stops (-x) on the cheapest test. The training runs of
# tests/training/test_run.py (two 30,000-step runs, ~200 s a call on the shared 2-core machine) are left out: see
# docs/mutation.md.
MODULES = {
    "evaluation/metrics.py": ["evaluation/test_metrics.py", "evaluation/test_protocol.py", "ekm/test_data.py"],
    "evaluation/protocol.py": ["evaluation/test_metrics.py", "evaluation/test_protocol.py", "ekm/test_data.py"],
    "training/schedules.py": ["training/test_schedules.py", "training/test_online.py", "ekm/test_data.py",
                              "training/test_reference.py"],
    "training/online.py": ["training/test_online.py", "ekm/test_data.py", "training/test_reference.py"],
    "planner/checkpoints.py": ["planner/test_checkpoints.py", "planner/test_search.py", "planner/test_graph.py",
                               "planner/test_plan.py"],
    "planner/slippery.py": ["planner/test_slippery.py", "planner/test_quadtree.py", "planner/test_graph.py",
                            "planner/test_checkpoints.py", "planner/test_search.py", "planner/test_plan.py"],
    "planner/search.py": ["planner/test_search.py", "planner/test_graph.py", "planner/test_checkpoints.py",
                          "planner/test_plan.py"],
    "ekm/kohonen.py": ["ekm/test_kohonen.py", "ekm/test_charts.py", "ekm/test_indirect.py", "ekm/test_direct.py",
                       "ekm/test_maps.py", "ekm/test_config.py", *CONTROLLER_TESTS],
    "ekm/charts.py": ["ekm/test_kohonen.py", "ekm/test_charts.py", "ekm/test_indirect.py", "ekm/test_direct.py",
                      "ekm/test_maps.py", "ekm/test_config.py", *CONTROLLER_TESTS],
    "ekm/indirect.py": ["ekm/test_kohonen.py", "ekm/test_charts.py", "ekm/test_indirect.py", "ekm/test_direct.py",
                        "ekm/test_maps.py", "ekm/test_config.py", *CONTROLLER_TESTS],
    "ekm/direct.py": ["ekm/test_kohonen.py", "ekm/test_charts.py", "ekm/test_indirect.py", "ekm/test_direct.py",
                      "ekm/test_maps.py", "ekm/test_config.py", *CONTROLLER_TESTS],
}

# The same lists in the flat tests/ of the commits before the tests mirrored the packages (3b8e0bf and its
# successors up to the move): used for a clone that has none of the files above.
FLAT_MODULES = {
    "evaluation/metrics.py": ["test_metrics_known.py", "test_protocol_known2.py", "test_shipped_maps.py"],
    "evaluation/protocol.py": ["test_metrics_known.py", "test_protocol_known2.py", "test_shipped_maps.py"],
    "training/schedules.py": ["test_schedules_known.py", "test_training_known.py", "test_shipped_maps.py",
                              "test_reference.py"],
    "training/online.py": ["test_training_known.py", "test_shipped_maps.py", "test_reference.py"],
    "planner/checkpoints.py": ["test_checkpoints_known.py", "test_search_known.py", "test_planner_search.py",
                               "test_planner_worlds.py"],
    "planner/slippery.py": ["test_slippery_known.py", "test_planner_coarseness.py", "test_planner_cells.py",
                            "test_planner_search.py", "test_planner_worlds.py"],
    "planner/search.py": ["test_search_known.py", "test_planner_search.py", "test_planner_worlds.py"],
    "ekm/kohonen.py": ["test_ekm_known.py", "test_ekm_known2.py", "test_charts.py", "test_ekm_maps.py",
                       "test_controllers.py"],
    "ekm/charts.py": ["test_ekm_known.py", "test_ekm_known2.py", "test_charts.py", "test_ekm_maps.py",
                      "test_controllers.py"],
    "ekm/indirect.py": ["test_ekm_known.py", "test_ekm_known2.py", "test_ekm_maps.py", "test_controllers.py"],
    "ekm/direct.py": ["test_ekm_known.py", "test_ekm_known2.py", "test_ekm_maps.py", "test_controllers.py"],
}


def mutants(root: Path, module: str):
    """All mutmut 2 mutants of a module, in mutmut's order: (index, id, mutated source, diff lines)."""
    source = (root / module).read_text()
    ids = list_mutations(Context(source=source, filename=module, dict_synonyms=[]))
    for i, mid in enumerate(ids):
        mutated, n = mutate(Context(source=source, filename=module, mutation_id=mid, dict_synonyms=[]))
        assert n == 1, (module, mid)
        diff = [line for line in difflib.unified_diff(source.splitlines(), mutated.splitlines(), lineterm="", n=0)
                if line[:1] in "+-" and line[:3] not in ("+++", "---")]
        yield i, mid, mutated, diff


def tests_in(root: Path, module: str) -> list[str]:
    """The module's test files present in the clone: in its package-mirroring tests/, else in a flat one."""
    for table in (MODULES, FLAT_MODULES):
        tests = [f"tests/{t}" for t in table[module] if (root / "tests" / t).exists()]
        if tests:
            return tests
    return []


def serial() -> list[str]:
    """pytest options for one process: the default run spreads files over xdist workers (-n auto), which would
    start workers for every mutant and lose the cheapest-test-first order that -x relies on."""
    return ["-n", "0"] if importlib.util.find_spec("xdist") else []


def run_tests(root: Path, tests: list[str], timeout: float) -> tuple[str, float]:
    env = dict(os.environ, PYTHONPATH=str(root), PYTHONDONTWRITEBYTECODE="1")
    cmd = [sys.executable, "-m", "pytest", "-x", "-q", "-p", "no:cacheprovider", "-p", "no:randomly", *serial(), *tests]
    t0 = time.monotonic()
    try:
        proc = subprocess.run(cmd, cwd=root, env=env, capture_output=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return "timeout", time.monotonic() - t0
    # 0: all passed -> survived; 1: a test failed -> killed; anything else (errors, no tests) -> killed too but flagged
    status = {0: "survived", 1: "killed"}.get(proc.returncode, f"killed-rc{proc.returncode}")
    return status, time.monotonic() - t0


def report(after_path: Path, before_path: Path | None = None, extra_path: Path | None = None) -> None:
    """Per-module score table (markdown). A mutant absent from the before file survived the after suite; the
    before suite is a subset of the after suite, so it survives that too (counted so, without a run). An
    ``extra`` file holds re-runs of some mutants with more tests: a third column, with those results."""
    def load(p):
        return {r["id"]: r for r in map(json.loads, p.read_text().splitlines())} if p and p.exists() else {}

    after, before, extra = load(after_path), load(before_path), load(extra_path)
    rows = {}
    for key, rec in after.items():
        b = before.get(key, {}).get("status") or ("survived" if rec["status"] == "survived" else None)
        e = extra.get(key, rec)["status"]
        row = rows.setdefault(key.split(":")[0], [0, 0, 0, 0, 0])
        for j, hit in enumerate((True, b not in (None, "survived"), rec["status"] != "survived",
                                 e != "survived", b is None)):
            row[j] += hit
    head = "| module | mutants | killed before | killed after |" + (" with the new tests |" if extra else "")
    print(head)
    print("|---|" + "---:|" * (head.count("|") - 2))

    def cells(name, n, kb, ka, ke, missing):
        pct = lambda k: f"{k} ({100 * k / n:.0f} %)"  # noqa: E731
        out = f"| {name} | {n} | {pct(kb)}{f' + {missing} not run' if missing else ''} | {pct(ka)} |"
        return out + (f" {pct(ke)} |" if extra else "")

    total = [0, 0, 0, 0, 0]
    for module in [m for m in MODULES if m in rows]:
        total = [a + b for a, b in zip(total, rows[module])]
        print(cells(module, *rows[module]))
    print(cells("**all**", *total))


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--root", type=Path, help="clone whose modules are mutated and whose tests run")
    ap.add_argument("--report", type=Path, nargs="+", metavar="JSONL",
                    help="AFTER [BEFORE [EXTRA]]: print the score table from these JSON lines and exit")
    ap.add_argument("--every", type=int, default=8, help="sample: mutants with index %% every == offset")
    ap.add_argument("--offset", type=int, default=0)
    ap.add_argument("--modules", nargs="*", default=list(MODULES))
    ap.add_argument("--ids", type=Path, help="run only these mutants (lines 'module:index'), ignoring the sample")
    ap.add_argument("--killed-in", type=Path, help="run only the mutants killed in this JSON lines file")
    ap.add_argument("--survived-in", type=Path, help="run only the mutants that survived in this JSON lines file")
    ap.add_argument("--out", type=Path, help="JSON lines; mutants already in it are skipped")
    ap.add_argument("--timeout", type=float, default=300.0)
    ap.add_argument("--list", action="store_true", help="print the sampled mutants and exit")
    args = ap.parse_args(argv)
    if args.report:
        return report(*args.report[:3])
    if args.root is None or (args.out is None and not args.list):
        ap.error("--root and --out are needed (--out not with --list)")
    root = args.root.resolve()
    wanted = set(args.ids.read_text().split()) if args.ids else None
    for path, killed in ((args.killed_in, True), (args.survived_in, False)):
        if path:
            records = map(json.loads, path.read_text().splitlines())
            wanted = {r["id"] for r in records if (r["status"] != "survived") == killed}
    done = set()
    if args.out and args.out.exists():
        done = {json.loads(line)["id"] for line in args.out.read_text().splitlines() if line.strip()}
    for module in args.modules:
        tests = tests_in(root, module)
        path = root / module
        original = path.read_text()
        try:
            for i, mid, mutated, diff in mutants(root, module):
                key = f"{module}:{i}"
                if wanted is not None:
                    if key not in wanted:
                        continue
                elif i % args.every != args.offset:
                    continue
                if args.list:
                    print(key, mid.line_number + 1, " | ".join(diff))
                    continue
                if key in done:
                    continue
                path.write_text(mutated)
                try:
                    status, seconds = run_tests(root, tests, args.timeout)
                finally:
                    path.write_text(original)
                rec = {"id": key, "line": mid.line_number + 1, "diff": diff, "status": status,
                       "seconds": round(seconds, 1), "tests": tests}
                with args.out.open("a") as f:
                    f.write(json.dumps(rec) + "\n")
                print(key, status, f"{seconds:.0f}s", " | ".join(diff), flush=True)
        finally:
            path.write_text(original)


if __name__ == "__main__":
    main()
