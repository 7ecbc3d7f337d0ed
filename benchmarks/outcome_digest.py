"""Fingerprints of every run of the README's compare table, to show that a speed change changed nothing.

Run from the repository root before and after a change, then compare the two files (about 1.5 minutes
on 2 cores)::

    python benchmarks/outcome_digest.py before.json
    # ... change the code ...
    python benchmarks/outcome_digest.py after.json && cmp before.json after.json

For each architecture (fusion, fields, samba, schema), named world (all eight) and seed 0–9 it records
:meth:`evaluation.scenario.RunRecord.outcome` and a SHA-1 of the poses of every 16 ms sub-step and the
commands of every tick — far stricter than the aggregated ``ekm compare --json``. Runs go to two
worker processes (``--workers``).
"""

from __future__ import annotations

import argparse
import hashlib
import json
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

WORLDS = ("three-rooms-static,three-rooms-moving,three-rooms-changed,extended-obstacle,concave-obstacle,three-rooms,"
          "open-arena,moving-target").split(",")
ARCHITECTURES = ("fusion", "fields", "samba", "schema")


def cell(args) -> list[dict]:
    """Outcome and fingerprint of seeds 0..seeds-1 of one architecture on one world."""
    arch, world, seeds = args
    from evaluation.scenario import run_architecture
    from robots.controllers.spec import parse_architectures
    from robots.worldfile import load_world

    spec, w = parse_architectures(arch)[0], load_world(world)
    out = []
    for seed in range(seeds):
        rec = run_architecture(w, spec, seed=seed)
        h = hashlib.sha1(np.ascontiguousarray(rec.poses).tobytes())
        h.update(np.asarray(rec.commands).tobytes())
        out.append({**rec.outcome(), "poses_sha1": h.hexdigest(), "n": len(rec.poses)})
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", help="JSON file to write")
    ap.add_argument("--seeds", type=int, default=10, help="seeds 0.. per architecture and world (default 10)")
    ap.add_argument("--workers", type=int, default=2, help="worker processes (default 2)")
    args = ap.parse_args(argv)
    jobs = [(a, w, args.seeds) for a in ARCHITECTURES for w in WORLDS]
    with ProcessPoolExecutor(args.workers) as ex:
        runs = [r for rs in ex.map(cell, jobs) for r in rs]
    Path(args.out).write_text(json.dumps(runs, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
