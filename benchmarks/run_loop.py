"""Runs of one architecture on every named world, over and over: something for a sampling profiler to watch.

Run from the repository root::

    pip install py-spy                                   # not a dependency of ekm
    python benchmarks/run_loop.py fields --rounds 6 &    # warm-up first, then prints "warm"
    sleep 25; py-spy record -p $! -r 1000 -d 15 -f raw -o fields.txt

Each round runs seeds 0–2 on each named world with the architecture's shipped map, pinned to
one CPU as ``ekm compare``'s workers run (:mod:`evaluation.pinning`). The warm-up (one run a world)
compiles the controller before "warm" is printed, so that samples taken after it are of steady runs;
the last line is the real-time factor of the timed rounds. A sampling profiler slows the run down far
less than ``cProfile`` or ``line_profiler``, whose cost per call or per line distorts a tick made of many
small calls (``docs/speed.md``, fifth round).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout without installing

from evaluation.pinning import pin_to_one_cpu  # noqa: E402

def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("architecture", help="one architecture as ekm run spells it, e.g. fields or samba:directions=36")
    ap.add_argument("--rounds", type=int, default=4, help="timed rounds of seeds 0-2 on every named world (default 4)")
    args = ap.parse_args(argv)
    if args.rounds < 1:
        ap.error("--rounds must be >= 1")
    pin_to_one_cpu()

    from ekm.errors import InputError
    from evaluation.scenario import run_architecture
    from robots.controllers.spec import parse_architectures
    from robots.worldfile import load_world, named_worlds

    try:
        specs = parse_architectures(args.architecture)
    except InputError as exc:
        ap.error(f"architecture: {exc}")
    if len(specs) != 1:
        ap.error(f"architecture: give one, got {len(specs)}")
    spec = specs[0]
    worlds = [load_world(name) for name in named_worlds()]
    for world in worlds:
        run_architecture(world, spec, seed=0)
    print("warm", flush=True)
    time.sleep(1)  # time to attach a profiler
    t0, simulated = time.perf_counter(), 0.0
    for _ in range(args.rounds):
        for world in worlds:
            for seed in range(3):
                simulated += run_architecture(world, spec, seed=seed).time_s
    print(f"{spec.label}: {simulated / (time.perf_counter() - t0):.0f}x real time over {args.rounds} rounds")
    return 0


if __name__ == "__main__":
    sys.exit(main())
