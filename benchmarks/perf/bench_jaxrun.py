"""The scenario runner on the JAX engine (``evaluation.jaxrun``) against the batch size: compile time, then runs per
second and simulated seconds per wall second of one architecture's batch in one world, seeds 0..B-1; and the same
runs one at a time on pymunk (``evaluation.scenario``) for the ratio.

    python benchmarks/perf/bench_jaxrun.py
    python benchmarks/perf/bench_jaxrun.py --architecture fields --world three-rooms --batches 1,16,64,256 --pymunk 8
    python benchmarks/perf/bench_jaxrun.py --architecture samba --batches 128 --pymunk 0 --look-back 0

Each batch size is run twice: the first call compiles (its wall time less the second's is the compile time, one per
architecture and shape), the second is the throughput. The batch uses every device JAX has as one (no sharding).
"""

from __future__ import annotations

import argparse
import time


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--architecture", default="schema")
    ap.add_argument("--world", default="three-rooms")
    ap.add_argument("--batches", default="1,8,32,128", help="batch sizes, comma-separated")
    ap.add_argument("--pymunk", type=int, default=8, help="runs on pymunk for the ratio (0: none)")
    ap.add_argument("--look-back", type=int, default=None,
                    help="the runner's look back (ScenarioConfig.look_back; default: its default)")
    args = ap.parse_args()

    import jax

    from evaluation import jaxrun
    from evaluation.scenario import ScenarioConfig, driver, run_scenario
    from robots.controllers.spec import parse_architecture
    from robots.worldnames import load_world

    spec, world, config = parse_architecture(args.architecture), load_world(args.world), ScenarioConfig()
    if args.look_back is not None:
        config = ScenarioConfig(look_back=args.look_back)
    print(f"{args.architecture} in {args.world}, devices {jax.devices()}")
    print("engine  batch  compile s  wall s  runs/s  sim s / wall s  reached")
    for b in [int(x) for x in args.batches.split(",")]:
        controller = driver(spec, seed=0).controller  # one map (trial 0) for the whole batch
        runs = [(world, seed) for seed in range(b)]
        t0 = time.perf_counter()
        jaxrun.run_scenarios(runs, controller, config)
        first = time.perf_counter() - t0
        t0 = time.perf_counter()
        recs = jaxrun.run_scenarios(runs, controller, config)
        wall = time.perf_counter() - t0
        sim = sum(r.times[-1] for r in recs)
        print(f"jax     {b:5d}  {first - wall:9.1f}  {wall:6.2f}  {b / wall:6.1f}  {sim / wall:14.0f}  "
              f"{sum(r.reached for r in recs)}/{b}")
    if args.pymunk:
        controller = driver(spec, seed=0).controller
        run_scenario(world, controller, seed=0, config=config)  # compile the step
        t0 = time.perf_counter()
        recs = [run_scenario(world, controller, seed=s, config=config) for s in range(args.pymunk)]
        wall = time.perf_counter() - t0
        sim = sum(r.times[-1] for r in recs)
        print(f"pymunk  {args.pymunk:5d}  {'':9s}  {wall:6.2f}  {args.pymunk / wall:6.1f}  {sim / wall:14.0f}  "
              f"{sum(r.reached for r in recs)}/{args.pymunk}")


if __name__ == "__main__":
    main()
