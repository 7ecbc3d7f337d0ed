"""Long comparisons: peak memory against the number of runs, and the table with workers killed mid-run.

    python benchmarks/perf/bench_compare.py memory --runs 500,10000      # peak RSS of the comparing process
    python benchmarks/perf/bench_compare.py faults --runs 2000 --every 30  # a random worker killed every 30 s

``memory`` runs each comparison in a fresh process and reports its peak resident memory (``ru_maxrss``; the
workers are separate processes) with the time taken. ``faults`` runs the same comparison twice, undisturbed
and with a random local worker killed (SIGKILL, as the out-of-memory killer does) every ``--every`` seconds,
and says whether the two tables are the same. By default the runs are short (``--time-limit`` 4 simulated s,
in open-arena and three-rooms-static) so that thousands fit in minutes: ``memory`` measures the comparison's
bookkeeping, not the runs; give ``faults`` runs long enough for kills to land mid-run (the docs use
``--worlds three-rooms-static,concave-obstacle --time-limit 120``).
"""

from __future__ import annotations

import argparse
import json
import os
import random
import resource
import signal
import subprocess
import sys
import threading
import time

WORLDS = ["open-arena", "three-rooms-static"]
ARCHITECTURES = "fusion,samba"


def one(runs: int, time_limit: float, workers: int, out: str | None = None) -> dict:
    """One comparison of about ``runs`` runs in this process; its table, wall time and peak memory."""
    import ekm

    trials = max(1, runs // (len(WORLDS) * 2))
    t0 = time.perf_counter()
    table = ekm.compare(WORLDS, ARCHITECTURES, trials=trials, time_limit=time_limit, workers=workers, out=out)
    seconds = time.perf_counter() - t0
    doc = table.to_dict()
    return {"runs": len(table.records), "seconds": round(seconds, 1),
            "peak_rss_mb": round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, 1),
            "results": doc["results"]}


def in_fresh_process(runs: int, args) -> dict:
    cmd = [sys.executable, __file__, "one", "--runs", str(runs), "--time-limit", str(args.time_limit),
           "--workers", str(args.workers), "--worlds", ",".join(WORLDS)]
    return json.loads(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout)


def memory(args) -> None:
    print(f"peak memory of ekm compare ({', '.join(WORLDS)}; {ARCHITECTURES}; {args.time_limit:g} s runs; "
          f"{args.workers} workers)")
    print(f"{'runs':>8} {'seconds':>8} {'peak RSS MB':>12}")
    first = None
    for n in args.runs:
        r = in_fresh_process(n, args)
        first = first or r["peak_rss_mb"]
        print(f"{r['runs']:>8} {r['seconds']:>8.1f} {r['peak_rss_mb']:>12.1f}  ({r['peak_rss_mb'] / first - 1:+.1%})",
              flush=True)


def workers_of(pid: int) -> list[int]:
    """The spawned worker processes among ``pid``'s children."""
    kids = subprocess.run(["pgrep", "-P", str(pid)], capture_output=True, text=True).stdout.split()
    found = []
    for k in kids:
        try:
            if b"spawn_main" in open(f"/proc/{k}/cmdline", "rb").read():
                found.append(int(k))
        except OSError:
            pass
    return found


def faults(args) -> None:
    (n,) = args.runs
    print(f"{n} runs ({', '.join(WORLDS)}; {ARCHITECTURES}; {args.time_limit:g} s runs; {args.workers} workers)")
    calm = in_fresh_process(n, args)
    print(f"undisturbed: {calm['runs']} runs in {calm['seconds']:.0f} s", flush=True)
    cmd = [sys.executable, __file__, "one", "--runs", str(n), "--time-limit", str(args.time_limit),
           "--workers", str(args.workers), "--worlds", ",".join(WORLDS)]
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, text=True)
    kills, rng = [], random.Random(args.seed)
    stop = threading.Event()

    def killer():
        while not stop.wait(args.every):
            found = workers_of(p.pid)
            if found:
                victim = rng.choice(found)
                try:
                    os.kill(victim, signal.SIGKILL)
                    kills.append(victim)
                except ProcessLookupError:
                    pass

    thread = threading.Thread(target=killer, daemon=True)
    thread.start()
    out, _ = p.communicate()
    stop.set()
    hit = json.loads(out)
    failed = sum(r["failed"] for r in hit["results"])
    same = hit["results"] == calm["results"]
    print(f"a worker killed every {args.every:g} s: {len(kills)} killed, {hit['runs']} runs in {hit['seconds']:.0f} s, "
          f"{failed} failed; the same table: {'yes' if same else 'NO'}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("what", choices=("memory", "faults", "one"))
    parser.add_argument("--runs", default=None, help="comma-separated run counts (memory: 500,10000; faults: 2000)")
    parser.add_argument("--time-limit", type=float, default=4.0, help="simulated seconds per run (default 4)")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--worlds", default=",".join(WORLDS), help=f"comma-separated (default {','.join(WORLDS)})")
    parser.add_argument("--every", type=float, default=30.0, help="faults: seconds between kills (default 30)")
    parser.add_argument("--seed", type=int, default=0, help="faults: which worker is killed")
    args = parser.parse_args()
    default = {"memory": "500,10000", "faults": "2000", "one": "500"}[args.what]
    args.runs = [int(x) for x in (args.runs or default).split(",")]
    WORLDS[:] = args.worlds.split(",")
    if args.what == "one":
        print(json.dumps(one(args.runs[0], args.time_limit, args.workers)))
    elif args.what == "memory":
        memory(args)
    else:
        faults(args)


if __name__ == "__main__":
    main()
