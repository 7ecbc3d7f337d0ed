"""The pymunk world of two trees in one process, alternating run by run: physics and IR µs per tick, same bits.

Run from the repository root, with another tree's checkout as the baseline (about a minute)::

    git worktree add /tmp/base fb4b94f
    python benchmarks/ab_world.py /tmp/base             # 2 rounds; --rounds 4 for more

Whole-run benchmarks on this 2-core machine move by ±30 % from one minute to the next, which hides a
5 % change in one part of a tick. Here both trees' :class:`robots.world.PymunkWorld` run in the same
process, one run each in turn: the commands every tick of real runs (each architecture on each named
world, seed 1, driven by this tree's runner) are replayed into a fresh world of each tree — ``sense``
then ``step`` a tick, as the runner calls them — and each tree's seconds in ``step`` (physics) and
``sense`` (IR) are summed. Every reading and every sub-step's pose must be the same in both trees, or the
script stops: a speed change of the world must not change what the robot does.

The baseline's ``robots/world.py`` is loaded under another module name; what it imports (kinematics,
sensors, world files) comes from this tree, so the comparison is of ``world.py`` alone.
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout without installing

from evaluation.pinning import pin_to_one_cpu  # noqa: E402

ARCHITECTURES = "fusion,fields,samba,schema"


def recorded_runs(seed: int) -> list:
    """(world, sensors, commands ``(ticks, 2)``) of each architecture's run on each named world (a map-driven
    architecture drives trial 0 of its shipped map)."""
    import jax

    from ekm.data import load_default_map
    from evaluation.scenario import run_scenario
    from robots.controllers.spec import parse_architectures
    from robots.worldfile import load_world, named_worlds

    runs = []
    for spec in parse_architectures(ARCHITECTURES):
        if spec.uses_map:
            maps = load_default_map(spec.default_chart)
            controller = spec.build(jax.tree.map(lambda a: a[0], maps.ekm), maps.cfg)
        else:
            controller = spec.build()
        for name in named_worlds():
            world = load_world(name)
            rec = run_scenario(world, controller, seed=seed)
            runs.append((world, controller.sensors, np.array([c[1:] for c in rec.commands]).reshape(-1, 2)))
    return runs


def replay(cls, world, sensors, commands, seed: int):
    """Seconds in ``sense`` and ``step`` of one replayed run, and what it read and where it went."""
    sim = cls(world, seed=seed)
    physics = sensing = 0.0
    readings, traces = [], []
    for command in commands:
        t0 = time.perf_counter()
        readings.append(sim.sense(sensors))
        t1 = time.perf_counter()
        traces.append(sim.step(command)[1])
        physics += time.perf_counter() - t1
        sensing += t1 - t0
    return physics, sensing, readings, traces


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("base", help="checkout of the baseline tree (it needs robots/world.py)")
    ap.add_argument("--rounds", type=int, default=2, help="rounds over all runs, each tree once a run (default 2)")
    ap.add_argument("--seed", type=int, default=1, help="seed of the recorded runs and of the replays (default 1)")
    args = ap.parse_args(argv)
    source = Path(args.base) / "robots" / "world.py"
    if not source.is_file():
        ap.error(f"{source}: no such file")
    if args.rounds < 1:
        ap.error("--rounds must be >= 1")
    cpu = pin_to_one_cpu()  # as ekm run and ekm compare's workers run

    spec = importlib.util.spec_from_file_location("base_world", source)
    base = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(base)
    from robots.world import PymunkWorld

    runs = recorded_runs(args.seed)
    trees = {"base": base.PymunkWorld, "this tree": PymunkWorld}
    total = {k: [0.0, 0.0] for k in trees}
    ticks = 0
    load = os.getloadavg()[0]
    for r in range(args.rounds):
        for world, sensors, commands in runs:
            order = list(trees) if r % 2 == 0 else list(trees)[::-1]  # who goes first alternates
            out = {}
            for label in order:
                physics, sensing, readings, traces = replay(trees[label], world, sensors, commands, args.seed)
                total[label][0] += physics
                total[label][1] += sensing
                out[label] = (readings, traces)
            (ra, ta), (rb, tb) = out.values()
            if not all(np.array_equal(a, b) for a, b in zip(ra + ta, rb + tb)):
                print(f"error: {world.name}: the two trees' worlds read or move differently", file=sys.stderr)
                return 1
            ticks += len(commands)
    print(f"{len(runs)} recorded runs (seed {args.seed}), {ticks // args.rounds} ticks, {args.rounds} rounds; "
          f"pinned to CPU {cpu}; 1-min load average {load:.1f} before, {os.getloadavg()[0]:.1f} after")
    print("| tree | physics µs/tick | IR sensing µs/tick |\n|---|---:|---:|")
    for label, (physics, sensing) in total.items():
        print(f"| {label} ({args.base if label == 'base' else '.'}) | {1e6 * physics / ticks:.1f} | "
              f"{1e6 * sensing / ticks:.1f} |")
    print("Every reading and every sub-step's pose was the same in both trees.")
    return 0


if __name__ == "__main__":
    sys.exit(main())
