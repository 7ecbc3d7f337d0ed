"""How long generating a world takes, per family (``robots.generator``; ``ekm worlds --generate``).

Run from the repository root::

    python benchmarks/perf/bench_generate.py

(options: ``--seeds 20`` seeds 0..N-1 per family, each at the difficulty its seed draws; ``--difficulty D``
to fix it). Prints a markdown table: per family the median and the largest wall time of one
:func:`robots.generator.generate` call (building, checking, the solvability search and its measures),
the range of the levels drawn, and the medians of the world's measures. The first call of the process is
made once before timing (imports, NumPy's first use).
"""

from __future__ import annotations

import argparse
import statistics
import time

from robots.generator import FAMILIES, generate


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=20, help="seeds 0..N-1 per family (default 20)")
    parser.add_argument("--difficulty", type=float, default=None, help="fixed difficulty (default: drawn)")
    args = parser.parse_args(argv)

    generate("maze", 0)  # warm up: imports and NumPy's first calls are not the generator's time
    level = "drawn from the seed" if args.difficulty is None else args.difficulty
    print(f"{args.seeds} seeds per family, difficulty {level}\n")
    print("| family | median s | max s | levels | narrowest passage m | route m | route ratio | turns |")
    print("|---|---:|---:|---|---:|---:|---:|---:|")
    for family in FAMILIES:
        times, worlds = [], []
        for seed in range(args.seeds):
            t0 = time.perf_counter()
            worlds.append(generate(family, seed, args.difficulty))
            times.append(time.perf_counter() - t0)
        d = [w.difficulty for w in worlds]

        def median(key):
            return statistics.median(getattr(x, key) for x in d)

        levels = [x.level for x in d]
        print(f"| {family} | {statistics.median(times):.3f} | {max(times):.3f} | {min(levels):.2f}-{max(levels):.2f} "
              f"| {median('narrowest_passage_m'):.3f} | {median('route_length_m'):.2f} | {median('route_ratio'):.2f} "
              f"| {median('turns'):g} |")


if __name__ == "__main__":
    main()
