"""How the work scales with cores: ``ekm compare`` on 1 and 2 worker processes, training on 1 and 2 JAX devices.

Run from the repository root (about 5 minutes on 2 cores with the defaults)::

    python benchmarks/perf/bench_scaling.py                       # both studies, markdown tables
    python benchmarks/perf/bench_scaling.py --only training       # training throughput only (about a minute)
    python benchmarks/perf/bench_scaling.py --only compare --workers 1,2 --trials 10

**Compare**: the README's table (``--worlds``: the eight named worlds, ``--architectures
fusion,fields,samba,schema``, ``--trials 10``: 320 runs) is run once per worker count as its own ``ekm
compare --json`` process; the table gives the wall time of the whole process (start-up, compiling the
controllers in every worker, the runs) and checks that every count gives the same results.

**Training**: each device count runs in its own process with
``XLA_FLAGS=--xla_force_host_platform_device_count=N``, where :func:`training.throughput.jax_trial_steps_per_s`
times ``train_chunk`` on the 15×15 map, 5 trials, trials spread as ``ekm train`` spreads them
(:func:`training.run.trial_layout`: 5 trials on 2 devices run as 3 + 3, a padding trial not counted).
With ``--protocol`` it also times the whole ``ekm train --mapping indirect`` (100,000 steps, the test
every 10,000) per device count.

Wall-clock numbers move with whatever else runs on the machine: the header prints the 1-minute load
average before and after.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

WORLDS = ("three-rooms-static,three-rooms-moving,three-rooms-changed,extended-obstacle,concave-obstacle,three-rooms,"
          "open-arena,moving-target")
ARCHITECTURES = "fusion,fields,samba,schema"

TRAINING = """
import json, sys
import jax
from ekm.config import EKMConfig
from training.throughput import jax_trial_steps_per_s
out = {m: jax_trial_steps_per_s(EKMConfig(mapping=m), steps=int(sys.argv[1])) for m in ("indirect", "direct")}
print(json.dumps({"devices": jax.device_count(), **out}))
"""


def env_with_devices(n: int) -> dict:
    flags = [f for f in os.environ.get("XLA_FLAGS", "").split() if "xla_force_host_platform_device_count" not in f]
    return {**os.environ, "XLA_FLAGS": " ".join(flags + [f"--xla_force_host_platform_device_count={n}"])}


def training(devices: list[int], steps: int, protocol: bool) -> list[dict]:
    rows = []
    for n in devices:
        proc = subprocess.run([sys.executable, "-c", TRAINING, str(steps)], capture_output=True, text=True,
                              env=env_with_devices(n), check=True)
        r = json.loads(proc.stdout.strip().splitlines()[-1])
        row = {"devices": n, "used": r["indirect"]["devices"],
               "indirect": r["indirect"]["trial_steps_per_s"], "direct": r["direct"]["trial_steps_per_s"],
               "indirect_median": r["indirect"]["median_trial_steps_per_s"],
               "direct_median": r["direct"]["median_trial_steps_per_s"]}
        if protocol:
            with tempfile.TemporaryDirectory() as tmp:
                t0 = time.perf_counter()
                subprocess.run([sys.executable, "-m", "ekm.cli", "train", "--mapping", "indirect", "--out",
                                str(Path(tmp) / "maps.npz")], capture_output=True, text=True,
                               env=env_with_devices(n), check=True)
                row["protocol_s"] = time.perf_counter() - t0
        rows.append(row)
    return rows


def compare(workers: list[int], trials: int) -> list[dict]:
    rows, first = [], None
    for w in workers:
        cmd = [sys.executable, "-m", "ekm.cli", "compare", "--worlds", WORLDS, "--architectures", ARCHITECTURES,
               "--trials", str(trials), "--workers", str(w), "--json"]
        t0 = time.perf_counter()
        proc = subprocess.run(cmd, capture_output=True, text=True, check=True)
        wall = time.perf_counter() - t0
        results = json.loads(proc.stdout)["results"]
        first = results if first is None else first
        rows.append({"workers": w, "runs": len(results) * trials, "wall_s": wall, "same_results": results == first})
    return rows


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", choices=("training", "compare"), help="run one study only")
    ap.add_argument("--workers", default="1,2", help="compare: worker counts, comma-separated (default 1,2)")
    ap.add_argument("--trials", type=int, default=10, help="compare: runs per architecture and world (default 10)")
    ap.add_argument("--devices", default="1,2", help="training: host device counts, comma-separated (default 1,2)")
    ap.add_argument("--steps", type=int, default=5000, help="training: steps per timed chunk (default 5000)")
    ap.add_argument("--protocol", action="store_true", help="training: also time the whole ekm train per device count")
    ap.add_argument("--json", action="store_true", help="print the numbers as JSON")
    args = ap.parse_args(argv)
    load = os.getloadavg()[0]
    out = {}
    if args.only in (None, "training"):
        out["training"] = training([int(n) for n in args.devices.split(",")], args.steps, args.protocol)
    if args.only in (None, "compare"):
        out["compare"] = compare([int(w) for w in args.workers.split(",")], args.trials)
    out["load_average_1min"] = [load, os.getloadavg()[0]]
    if args.json:
        print(json.dumps(out, indent=2))
        return 0
    print(f"{os.cpu_count()} cores; 1-min load average {load:.1f} before, {os.getloadavg()[0]:.1f} after "
          "(more than 0 means other work shared the CPU)")
    if "training" in out:
        base = out["training"][0]
        print("\n(trial-steps/s of the best of 5 chunks, and their median)")
        print("\n| host devices | devices used | indirect trial-steps/s (median) | × | direct trial-steps/s (median) | × |"
              + (" ekm train indirect (s) |" if args.protocol else ""))
        print("|---:|---:|---:|---:|---:|---:|" + ("---:|" if args.protocol else ""))
        for r in out["training"]:
            print(f"| {r['devices']} | {r['used']} | {r['indirect']:,.0f} ({r['indirect_median']:,.0f}) | "
                  f"{r['indirect'] / base['indirect']:.2f} | {r['direct']:,.0f} ({r['direct_median']:,.0f}) | "
                  f"{r['direct'] / base['direct']:.2f} |" + (f" {r['protocol_s']:.1f} |" if args.protocol else ""))
    if "compare" in out:
        base = out["compare"][0]
        print("\n| compare workers | runs | wall s | speed-up | same results |")
        print("|---:|---:|---:|---:|---|")
        for r in out["compare"]:
            print(f"| {r['workers']} | {r['runs']} | {r['wall_s']:.1f} | {base['wall_s'] / r['wall_s']:.2f} | "
                  f"{'yes' if r['same_results'] else 'NO'} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
