"""The least wall time the JAX runner could take for a finished comparison: each architecture's simulated seconds in
its results file, divided by the best rate (simulated seconds per wall second) a batch of that architecture reaches
on this machine — with no planning, no replanning, no padding and no runs left waiting for their block.

    python benchmarks/perf/floor_jaxrun.py RESULTS.jsonl
    python benchmarks/perf/floor_jaxrun.py RESULTS.jsonl --batch 128 --world three-rooms

The rate is measured as ``bench_jaxrun.py`` measures it: one batch of ``--batch`` runs of the architecture in
``--world`` (seeds 0..B-1), called twice, the second call timed. A small world's scene is the cheapest to ray-cast,
so the floor errs low: a target under it cannot be met by any scheduling of the host's work, on this machine.
"""

from __future__ import annotations

import argparse
import json
import time
from collections import defaultdict


def simulated_seconds(path: str) -> dict[str, tuple[str, int, float]]:
    """``{label: (architecture spec, runs, simulated s)}`` of a results file (``ekm compare --out``)."""
    totals: dict = defaultdict(lambda: ["", 0, 0.0])
    with open(path) as fh:
        for line in fh:
            row = json.loads(line)
            if "outcome" not in row:
                continue
            out = row["outcome"]
            if out.get("time_s") is None:
                continue
            entry = totals[out["label"]]
            entry[0], entry[1], entry[2] = row["job"]["architecture"], entry[1] + 1, entry[2] + float(out["time_s"])
    return {k: tuple(v) for k, v in totals.items()}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("results", help="a finished comparison's results file (ekm compare --out)")
    ap.add_argument("--batch", type=int, default=128, help="runs in the batch that measures each rate")
    ap.add_argument("--world", default="three-rooms")
    args = ap.parse_args()

    import jax

    from evaluation import jaxrun
    from evaluation.scenario import ScenarioConfig, driver
    from robots.controllers.spec import parse_architecture
    from robots.worldnames import load_world

    world, config = load_world(args.world), ScenarioConfig()
    print(f"rates: batches of {args.batch} in {args.world}, devices {jax.devices()}")
    print("architecture  runs  simulated s  sim s / wall s  floor s")
    total = 0.0
    for label, (arch, runs, sim_needed) in simulated_seconds(args.results).items():
        controller = driver(parse_architecture(arch), seed=0).controller
        batch = [(world, seed) for seed in range(args.batch)]
        jaxrun.run_scenarios(batch, controller, config)  # compiles
        t0 = time.perf_counter()
        recs = jaxrun.run_scenarios(batch, controller, config)
        rate = sum(r.times[-1] for r in recs) / (time.perf_counter() - t0)
        total += sim_needed / rate
        print(f"{label:12s}  {runs:4d}  {sim_needed:11.0f}  {rate:14.0f}  {sim_needed / rate:7.1f}")
    print(f"all                                          {total:7.1f}")


if __name__ == "__main__":
    main()
