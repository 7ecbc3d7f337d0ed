"""What learning while driving costs (docs/performance.md): wall time per tick of a run, frozen and with --learn.

Run from the repository root (about a minute on two cores)::

    python benchmarks/perf/bench_learning.py                          # fields and fusion, three worlds
    python benchmarks/perf/bench_learning.py --architectures fields --worlds concave-obstacle --repeats 5

For each architecture and world, the same run (seed 0, the Khepera and the shipped map) is made frozen and with
the map learning (``learn``: the default rule), ``--repeats`` times each, interleaved so that a load on the machine
falls on both alike; the first run of each is a warm-up (compilation) and is not counted. Prints the median wall
time per tick of each and their ratio. The target (issue 32): learning costs at most 30 % more per tick.
"""

from __future__ import annotations

import argparse
import statistics
import time


def per_tick(world: str, architecture: str, learn, seed: int = 0) -> float:
    """Wall seconds per tick of one run."""
    import ekm

    t0 = time.perf_counter()
    out = ekm.run(world, architecture, seed=seed, learn=learn)
    return (time.perf_counter() - t0) / max(1, len(out.record.commands))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--architectures", default="fields,fusion")
    parser.add_argument("--worlds", default="three-rooms-static,concave-obstacle,open-arena")
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    from evaluation.pinning import pin_to_one_cpu

    pin_to_one_cpu()
    print(f"{'architecture':12s} {'world':20s} {'frozen ms/tick':>15s} {'learning ms/tick':>17s} {'ratio':>6s}")
    for arch in args.architectures.split(","):
        for world in args.worlds.split(","):
            per_tick(world, arch, None), per_tick(world, arch, True)  # warm-up: compile both steps
            frozen, learning = [], []
            for _ in range(args.repeats):
                frozen.append(per_tick(world, arch, None))
                learning.append(per_tick(world, arch, True))
            f, g = statistics.median(frozen), statistics.median(learning)
            print(f"{arch:12s} {world:20s} {1000 * f:15.3f} {1000 * g:17.3f} {g / f:6.2f}")


if __name__ == "__main__":
    main()
