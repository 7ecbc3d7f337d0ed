"""A/B the training throughput of two (or more) source trees, alternating them to cancel this machine's drift.

Run from the repository root (about 2 minutes with the defaults)::

    git worktree add /tmp/base a398745                 # the tree to compare against
    python benchmarks/ab_training.py /tmp/base .       # 3 rounds × (each tree × 1 and 2 host devices)
    python benchmarks/ab_training.py /tmp/base . --rounds 5 --devices 2 --mapping direct

Each measurement is its own process with the tree first on ``PYTHONPATH`` and
``XLA_FLAGS=--xla_force_host_platform_device_count=D``: 15×15 map, 5 trials spread as ``ekm train`` spreads
them (``training.run.trial_layout``; a padding trial is not counted), one compiled chunk of 5,000 steps
timed 9 times (``training.run.chunk``, present in every tree since the trials were spread over devices).
It prints the median and best chunk per tree and device count, round by round and over all rounds. Single
chunks on this machine vary by ±30 %, so compare medians, round by round.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

TIMED = """
import json, sys, time
import jax
from ekm.config import EKMConfig
from training.online import TrainConfig, start
from training.run import chunk, trial_layout
cfg, tcfg = EKMConfig(mapping=sys.argv[1]), TrainConfig(steps=100_000, trials=5)
padded, sharding = trial_layout(5, None)
keys = jax.random.split(jax.random.PRNGKey(0), padded)
s = jax.vmap(lambda k: start(k, cfg, tcfg))(keys)
if sharding is not None:
    s, keys = jax.device_put((s, keys), sharding)
jax.block_until_ready(chunk(s, keys, 0.0, length=5000, cfg=cfg, tcfg=tcfg, sharding=sharding))
rates = []
for i in range(9):
    t = time.perf_counter()
    s = jax.block_until_ready(chunk(s, keys, float(i * 5000), length=5000, cfg=cfg, tcfg=tcfg, sharding=sharding))
    rates.append(25000 / (time.perf_counter() - t))
print(json.dumps(rates))
"""


def measure(tree: Path, devices: int, mapping: str) -> list[float]:
    """Trial-steps/s of 9 chunks of ``tree``'s training loop on ``devices`` host devices."""
    flags = [f for f in os.environ.get("XLA_FLAGS", "").split() if "xla_force_host_platform_device_count" not in f]
    env = {**os.environ, "PYTHONPATH": str(tree.resolve()),
           "XLA_FLAGS": " ".join(flags + [f"--xla_force_host_platform_device_count={devices}"])}
    proc = subprocess.run([sys.executable, "-c", TIMED, mapping], capture_output=True, text=True, env=env,
                          cwd=tree, check=True)
    return json.loads(proc.stdout.strip().splitlines()[-1])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("trees", nargs="+", type=Path, help="source trees (checkouts) to compare")
    ap.add_argument("--rounds", type=int, default=3, help="alternations (default 3)")
    ap.add_argument("--devices", default="1,2", help="host device counts, comma-separated (default 1,2)")
    ap.add_argument("--mapping", default="indirect", choices=("indirect", "direct"))
    args = ap.parse_args(argv)
    for tree in args.trees:
        if not (tree / "training" / "run.py").is_file():
            print(f"ab_training.py: {tree} is not an ekm source tree (no training/run.py)", file=sys.stderr)
            return 2
    devices = [int(d) for d in args.devices.split(",")]
    load = os.getloadavg()[0]
    every: dict = {}
    print("| round | tree | host devices | median trial-steps/s | best |\n|---:|---|---:|---:|---:|")
    for r in range(args.rounds):
        for tree in args.trees:
            for d in devices:
                rates = measure(tree, d, args.mapping)
                every.setdefault((str(tree), d), []).extend(rates)
                print(f"| {r + 1} | {tree} | {d} | {np.median(rates):,.0f} | {max(rates):,.0f} |", flush=True)
    print("\n| tree | host devices | median of all chunks | best |\n|---|---:|---:|---:|")
    for (tree, d), rates in every.items():
        print(f"| {tree} | {d} | {np.median(rates):,.0f} | {max(rates):,.0f} |")
    print(f"\n{args.mapping}, 15×15, 5 trials; 1-min load average {load:.1f} before, {os.getloadavg()[0]:.1f} after")
    return 0


if __name__ == "__main__":
    sys.exit(main())
