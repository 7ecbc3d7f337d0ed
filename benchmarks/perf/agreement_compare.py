"""Do ``ekm compare``'s two engines agree? The same comparison on pymunk and on the JAX engine (``--engine jax``),
side by side: per world and architecture, the runs that reached the goal with their 95 % Wilson intervals, the
collisions, the mean time of the runs that reached and the recoveries (traps replanned round).

    python benchmarks/perf/agreement_compare.py --out agreement        # runs both, keeps agreement-{engine}.jsonl
    python benchmarks/perf/agreement_compare.py --from agreement       # the table of two finished results files

Defaults: the named worlds, fusion, fields, samba and schema, 10 trials (seeds 0-9). The table of
docs/guide/jaxworld.md is this script's output.
"""

from __future__ import annotations

import argparse
import time

ENGINES = ("pymunk", "jax")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--worlds", default="open-arena,three-rooms,three-rooms-static,concave-obstacle,extended-obstacle,"
                    "three-rooms-moving,three-rooms-changed,moving-target")
    ap.add_argument("--architectures", default="fusion,fields,samba,schema")
    ap.add_argument("--trials", type=int, default=10)
    ap.add_argument("--out", metavar="PREFIX", help="run both engines, results to PREFIX-{engine}.jsonl")
    ap.add_argument("--from", dest="source", metavar="PREFIX", help="no runs: read PREFIX-{engine}.jsonl")
    args = ap.parse_args()
    if bool(args.out) == bool(args.source):
        ap.error("give --out PREFIX (run) or --from PREFIX (read)")

    import ekm

    tables = {}
    for engine in ENGINES:
        if args.out:
            t0 = time.perf_counter()
            tables[engine] = ekm.compare(args.worlds, args.architectures, trials=args.trials, engine=engine,
                                         out=f"{args.out}-{engine}.jsonl")
            print(f"{engine}: {len(tables[engine].records)} runs in {time.perf_counter() - t0:.0f} s")
        else:
            from ekm.api.comparing import load_comparison

            tables[engine] = load_comparison(f"{args.source}-{engine}.jsonl")
    print(table(tables))


def table(tables: dict) -> str:
    """The side-by-side table (Markdown) of the two engines' :class:`ekm.api.comparing.Table`."""
    from evaluation.compare import wilson

    runs = {}
    for engine, t in tables.items():
        for r in t.records:
            runs.setdefault((r["given"], r["label"]), {}).setdefault(engine, []).append(r)
    first = tables[ENGINES[0]]
    lines = ["| world | architecture | pymunk | 95 % interval | jax | 95 % interval | collisions (pymunk / jax) | "
             "time of reached runs, s (pymunk / jax) | recoveries (pymunk / jax) |", "|---|---|---|---|---|---|---|---|---|"]
    for world in first.worlds:
        for label in first.labels:
            cells, collisions, times, recoveries = [], [], [], []
            for engine in ENGINES:
                rs = runs[(world, label)][engine]
                k = sum(r["reached"] for r in rs)
                lo, hi = wilson(k, len(rs))
                cells.append(f"{k}/{len(rs)} | {lo:.2f}–{hi:.2f}")
                collisions.append(str(sum(r["collisions"] for r in rs)))
                ok = [r["time_s"] for r in rs if r["reached"]]
                times.append(f"{sum(ok) / len(ok):.1f}" if ok else "–")
                recoveries.append(str(sum(r["recoveries"] for r in rs)))
            lines.append(f"| {world} | {label} | {cells[0]} | {cells[1]} | {' / '.join(collisions)} | "
                         f"{' / '.join(times)} | {' / '.join(recoveries)} |")
    return "\n".join(lines)


if __name__ == "__main__":
    main()
