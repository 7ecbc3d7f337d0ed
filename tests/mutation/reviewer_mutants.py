"""The reviewer's hand mutations of issue 12 item 5, applied one at a time to a clone; reports which tests fail.

    python tests/mutation/reviewer_mutants.py --root <clone> [--out results.jsonl]

Each mutation replaces one exact line (it must occur once); the module's test files present in the clone run
without -x, so every test that kills the mutant is listed. The file is restored afterwards. Not collected by pytest.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
import re
import subprocess
import sys
import time
from pathlib import Path

# Paths under tests/, as it mirrors the packages; the flat names after them are for clones from before the move
# (only the files present in a clone run).
METRICS_TESTS = ["evaluation/test_metrics.py", "evaluation/test_protocol.py", "ekm/test_data.py",
                 "test_metrics_known.py", "test_shipped_maps.py"]
PLANNER_TESTS = ["planner/test_checkpoints.py", "planner/test_search.py", "planner/test_graph.py",
                 "planner/test_plan.py", "test_checkpoints_known.py", "test_search_known.py",
                 "test_planner_search.py", "test_planner_worlds.py"]

MUTATIONS = [
    ("T(eps) not divided by l_i", "evaluation/metrics.py",
     "t_norm = np.asarray(rec.time, dtype=float) / straight",
     "t_norm = np.asarray(rec.time, dtype=float)", METRICS_TESTS),
    ("D(eps) without its absolute value", "evaluation/metrics.py",
     "dev = np.abs(np.asarray(rec.path, dtype=float) - straight) / straight",
     "dev = (np.asarray(rec.path, dtype=float) - straight) / straight", METRICS_TESTS),
    ("a stop that does not hold", "evaluation/protocol.py",
     "stop_now = stopped | is_stop_command(c_p, params, jnp)",
     "stop_now = is_stop_command(c_p, params, jnp)", METRICS_TESTS),
    ("first-passage time one sub-step early", "evaluation/protocol.py",
     "time = jnp.where(new_hit, k + (first + 1.0) / n, time)",
     "time = jnp.where(new_hit, k + first / n, time)", METRICS_TESTS),
    ("first-passage path one sub-step early", "evaluation/protocol.py",
     "path = jnp.where(new_hit, cum[first], path)",
     "path = jnp.where(new_hit, cum[first] - seg[first], path)", METRICS_TESTS),
    ("schedules decaying backwards", "training/schedules.py",
     "s = jnp.clip(t / (self.fraction * total), 0.0, 1.0)",
     "s = 1.0 - jnp.clip(t / (self.fraction * total), 0.0, 1.0)",
     ["training/test_schedules.py", "training/test_online.py", "ekm/test_data.py", "training/test_reference.py",
      "test_schedules_known.py", "test_training_known.py", "test_shipped_maps.py", "test_reference.py"]),
    ("checkpoints measured from the start, not the previous checkpoint", "planner/checkpoints.py",
     "x, y = closest_point(x, y, graph.boundary[(a, b)])",
     "x, y = closest_point(float(start[0]), float(start[1]), graph.boundary[(a, b)])", PLANNER_TESTS),
]


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--root", type=Path, required=True)
    ap.add_argument("--out", type=Path)
    ap.add_argument("--only", type=int, nargs="*", help="indices into MUTATIONS")
    args = ap.parse_args(argv)
    root = args.root.resolve()
    env = dict(os.environ, PYTHONPATH=str(root), PYTHONDONTWRITEBYTECODE="1")
    serial = ["-n", "0"] if importlib.util.find_spec("xdist") else []  # one process: no xdist workers per mutant
    for i, (name, module, old, new, tests) in enumerate(MUTATIONS):
        if args.only is not None and i not in args.only:
            continue
        path = root / module
        original = path.read_text()
        assert original.count(old) == 1, (module, old)
        files = [f"tests/{t}" for t in tests if (root / "tests" / t).exists()]
        path.write_text(original.replace(old, new))
        t0 = time.monotonic()
        try:
            proc = subprocess.run([sys.executable, "-m", "pytest", "-q", "-rf", "-p", "no:cacheprovider",
                                   "-p", "no:randomly", *serial, *files], cwd=root, env=env, capture_output=True,
                                  text=True)
        finally:
            path.write_text(original)
        failed = re.findall(r"^FAILED (\S+)", proc.stdout, re.M)
        status = "survived" if proc.returncode == 0 else "killed"
        rec = {"mutation": name, "module": module, "old": old, "new": new, "status": status, "killed_by": failed,
               "tests": files, "seconds": round(time.monotonic() - t0, 1)}
        print(json.dumps(rec), flush=True)
        if args.out:
            with args.out.open("a") as f:
                f.write(json.dumps(rec) + "\n")


if __name__ == "__main__":
    main()
