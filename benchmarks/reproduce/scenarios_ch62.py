"""Thesis ch. 6.2 over many seeds: every architecture × world × seed through the scenario runner, as a table.

Run from the repository root (the default table: 7 architectures × 5 worlds × 10 seeds, 350 runs)::

    python benchmarks/reproduce/scenarios_ch62.py                                # the README's table
    python benchmarks/reproduce/scenarios_ch62.py --architectures fields:form=thesis,fields:commit=false --seeds 20
    python benchmarks/reproduce/scenarios_ch62.py --architectures fusion,fields:form=thesis --worlds extended-obstacle,concave-obstacle --recover
    python benchmarks/reproduce/scenarios_ch62.py --map other.npz               # another trained map for every architecture

Each cell: how many runs reached the goal (stopped there without a collision), how many the trap monitor
caught, how many ended some other way (C: arrived after a collision; L: time limit; N: no route after
a change of the map), the runs' collisions, and the mean time and path of the runs that reached the goal.
The letters per seed show which run did what (R reached, T trapped, C, L, N as above).

The runs are set up as the thesis's were: its greedy checkpoints (ch. 3.2.3) and no recovery, unless
``--checkpoints visible`` and ``--recover`` say otherwise (``ekm compare`` runs the package's defaults).

Runs spread over worker processes (``--workers``, default the machine's cores); each run is a pure
function of (world, architecture, seed), so the table does not depend on the number of workers.
"""

from __future__ import annotations

import argparse
import json
import multiprocessing as mp
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor

DEFAULT_WORLDS = ("three-rooms-static", "three-rooms-moving", "three-rooms-changed", "extended-obstacle",
                  "concave-obstacle")
DEFAULT_ARCHITECTURES = "fusion,fusion:sensors=long,period=0.128,fields,fields:form=thesis,samba,schema"
_MAPS: dict = {}


def one(job):
    """One run (in a worker process): its outcome record."""
    world, architecture, seed, recover, time_limit, trap_after, map_path, checkpoints = job
    from ekm.mapfile import load_maps
    from evaluation.scenario import ScenarioConfig, run_architecture
    from robots.controllers.spec import parse_architecture
    from robots.worldnames import load_world

    if map_path and map_path not in _MAPS:
        _MAPS[map_path] = load_maps(map_path)
    rec = run_architecture(load_world(world), parse_architecture(architecture), _MAPS.get(map_path), seed=seed,
                           config=ScenarioConfig(recover=recover, time_limit=time_limit, trap_after=trap_after,
                                                 checkpoints=checkpoints), source=map_path or "")
    return {**rec.outcome(), "label": architecture, "given": world}  # "given": the name or path as typed


def summarize(results: list[dict], worlds, architectures, seeds) -> list[dict]:
    from evaluation.compare import run_letter
    rows = []
    for arch in architectures:
        for world in worlds:
            rs = sorted((r for r in results if r["label"] == arch and r["given"] == world), key=lambda r: r["seed"])
            ok = [r for r in rs if r["reached"]]
            rows.append({"architecture": arch, "world": world, "runs": len(rs), "reached": len(ok),
                         "trapped": sum(r["trapped"] for r in rs), "collisions": sum(r["collisions"] for r in rs),
                         "recoveries": sum(r["recoveries"] for r in rs),
                         "mean_time_s": round(sum(r["time_s"] for r in ok) / len(ok), 2) if ok else None,
                         "mean_path_m": round(sum(r["path_m"] for r in ok) / len(ok), 3) if ok else None,
                         "runs_by_seed": "".join(run_letter(r) for r in rs)})
    return rows


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--architectures", default=DEFAULT_ARCHITECTURES,
                        help=f"as ekm run spells them, comma-separated (default {DEFAULT_ARCHITECTURES})")
    parser.add_argument("--worlds", default=",".join(DEFAULT_WORLDS), help="comma-separated named worlds or files")
    parser.add_argument("--seeds", type=int, default=10, help="seeds 0 .. N-1 (default 10)")
    parser.add_argument("--first-seed", type=int, default=0)
    parser.add_argument("--recover", action="store_true", help="cognizant-failure recovery on")
    parser.add_argument("--checkpoints", choices=("thesis", "visible"), default="thesis",
                        help="the planner's checkpoint rule (default thesis: ch. 3.2.3, as the thesis's runs)")
    parser.add_argument("--time-limit", type=float, default=120.0, help="simulated seconds per run (default 120)")
    parser.add_argument("--trap-after", type=float, default=20.0,
                        help="seconds without progress before the trap monitor fires (default 20)")
    parser.add_argument("--map", help="a map file for every architecture (default: each one's shipped map)")
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args(argv)

    from ekm.errors import InputError
    from robots.controllers.spec import parse_architectures
    from robots.worldnames import load_world

    try:  # every bad name or parameter before any run
        architectures = [s.label for s in parse_architectures(args.architectures)]
        worlds = [w.strip() for w in args.worlds.split(",")]
        for w in worlds:
            load_world(w)
    except InputError as exc:
        parser.error(str(exc))
    seeds = range(args.first_seed, args.first_seed + args.seeds)
    jobs = [(w, a, s, args.recover, args.time_limit, args.trap_after, args.map, args.checkpoints)
            for a in architectures for w in worlds for s in seeds]
    t0 = time.perf_counter()
    with ProcessPoolExecutor(args.workers, mp_context=mp.get_context("spawn")) as pool:
        results = list(pool.map(one, jobs, chunksize=2))
    rows = summarize(results, worlds, architectures, seeds)
    seconds = time.perf_counter() - t0
    if args.json:
        json.dump({"rows": rows, "seeds": list(seeds), "recover": args.recover, "seconds": round(seconds, 1)},
                  sys.stdout, indent=2)
        print()
        return 0
    print(f"seeds {seeds.start}-{seeds.stop - 1}{', recovery on' if args.recover else ''}; "
          f"{len(jobs)} runs in {seconds:.0f} s on {args.workers} workers")
    print("| architecture | world | reached | trapped | collisions | mean time (s) | mean path (m) | by seed |")
    print("|---|---|---:|---:|---:|---:|---:|---|")
    for r in rows:
        t = "" if r["mean_time_s"] is None else f"{r['mean_time_s']:.1f}"
        p = "" if r["mean_path_m"] is None else f"{r['mean_path_m']:.2f}"
        rec = f" ({r['recoveries']} recoveries)" if args.recover else ""
        print(f"| {r['architecture']} | {r['world']} | {r['reached']}/{r['runs']} | {r['trapped']}{rec} | "
              f"{r['collisions']} | {t} | {p} | {r['runs_by_seed']} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
