"""Planning time of large generated worlds (issue 35: "planning a 4 m world in well under a second").

Run from the repository root::

    python benchmarks/perf/bench_plan_large.py [--seeds 0 1 2] [--repeat 3]

For each ``large:SEED`` world (2-6 m a side, many rooms) it prints the world's size, the planned route's length and
the best of ``--repeat`` wall-clock times of :func:`planner.plan` with the Khepera's padding, each with the
planner's per-process caches (bitmaps, plans) cleared first. Most of such a plan is the visible checkpoints
(:mod:`planner.visibility`): the cell path search, and the legs :func:`planner.visibility.taut` tests, which it asks
in batches (:func:`planner.visibility.legs_clear`) and which are decided on a sixteenth of their sample points
where the slack's Lipschitz bound allows. Wall-clock times depend on the machine and its load; docs/performance.md
has today's.
"""

from __future__ import annotations

import argparse
import importlib
import time

from planner import plan
from planner.checkpoints import path_length
from robots.generator import generate
from robots.params import KHEPERA


def fresh_plan(world):
    """:func:`planner.plan` with every per-process cache cleared first (s, the plan). The module ``planner.plan`` is
    looked up by name: ``from planner import plan`` is the function, whose own attributes hold no cache."""
    for module in (importlib.import_module("planner.bitmap"), importlib.import_module("planner.plan")):
        for name in dir(module):
            cached = getattr(module, name)
            if hasattr(cached, "cache_clear"):
                cached.cache_clear()
    t = time.perf_counter()
    made = plan(world, padding=KHEPERA.radius)
    return time.perf_counter() - t, made


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    print("| world | size (m) | route (m) | plan (s, best of %d) |" % args.repeat)
    print("|---|---|---|---|")
    for seed in args.seeds:
        world = generate("large", seed)
        times, made = zip(*(fresh_plan(world) for _ in range(args.repeat)))
        route = path_length(world.start[:2], made[0].checkpoints)
        print(f"| large:{seed} | {world.size[0]:.2f} x {world.size[1]:.2f} | {route:.2f} | {min(times):.2f} |")


if __name__ == "__main__":
    main()
