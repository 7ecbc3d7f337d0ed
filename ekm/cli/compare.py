"""``ekm compare``: every architecture × world × trial through the scenario runner, in parallel, with
95 % intervals (DESIGN §6; :mod:`evaluation.compare`)."""

from __future__ import annotations

import os

from ekm.cli.args import nonneg_int, output_path, positive_float, positive_int, print_json, provenance, show_progress
from ekm.errors import InputError


def add_parser(sub) -> None:
    p = sub.add_parser("compare", help="compare architectures over worlds and seeds (parallel; Dask optional)")
    p.add_argument("--worlds", required=True, metavar="W1,W2,...", help="named worlds or world files, comma-separated")
    p.add_argument("--architectures", required=True, metavar="A1[:k=v,...],A2,...",
                   help="as ekm run spells them, comma-separated; a k=v after a comma continues the architecture "
                        "before it (fusion:sensors=long,beta=0.8,fields)")
    p.add_argument("--trials", type=positive_int, default=10, help="runs per architecture and world (default 10)")
    p.add_argument("--seed", type=nonneg_int, default=0,
                   help="trial i runs with seed SEED + i for every architecture and world (default 0)")
    p.add_argument("--workers", type=positive_int, default=None,
                   help=f"local worker processes (default: the machine's cores, {os.cpu_count()})")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="send the runs to a running Dask scheduler (tcp://host:8786; needs ekm[cluster])")
    p.add_argument("--map", metavar="MAP.npz", help="map for the EKM architectures (default: their shipped maps)")
    p.add_argument("--recover", action="store_true", help="cognizant-failure recovery on (thesis 7.1.1)")
    p.add_argument("--time-limit", type=positive_float, default=120.0, metavar="S",
                   help="simulated seconds per run (default 120)")
    p.add_argument("--plot", metavar="PNG", help="success rates with their intervals, and one path per cell")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=run)


def resolve(args):
    """Worlds, architectures, map and config, every one checked before any run starts."""
    from ekm.mapfile import load_maps
    from evaluation.scenario import ScenarioConfig
    from robots.controllers.spec import parse_architectures
    from robots.worldfile import load_world

    worlds = [w.strip() for w in args.worlds.split(",")]
    if not all(worlds):
        raise InputError(f"--worlds {args.worlds!r}: empty item between commas")
    if len(set(worlds)) != len(worlds):
        raise InputError(f"--worlds {args.worlds!r}: a world is named twice")
    for w in worlds:
        load_world(w)
    specs = parse_architectures(args.architectures)
    labels = [s.label for s in specs]
    if len(set(labels)) != len(labels):
        raise InputError(f"--architectures {args.architectures!r}: an architecture is named twice")
    if args.map:
        load_maps(args.map)
    return worlds, specs, ScenarioConfig(time_limit=args.time_limit, recover=args.recover)


def executor_for(args):
    """The executor the runs go to: a Dask cluster's (``--scheduler``) or a local process pool."""
    if args.scheduler:
        try:
            from distributed import Client
        except ImportError:
            raise InputError("--scheduler: Dask is not installed; pip install 'ekm[cluster]'") from None
        try:
            client = Client(args.scheduler, timeout="10s")
        except (OSError, TimeoutError, ValueError) as exc:
            raise InputError(f"--scheduler {args.scheduler}: cannot connect ({exc.__class__.__name__}: {exc})") from None
        return client.get_executor(pure=False), client
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    workers = args.workers or os.cpu_count() or 1
    # spawn, not fork: a forked JAX process can deadlock
    return ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("spawn")), None


def run(args) -> None:
    """Compare architectures over worlds and trials; print the table or the JSON, draw the plot."""
    import time

    from evaluation.compare import compare, jobs, summarize

    plot = output_path(args.plot, "--plot", ".png") if args.plot else None
    worlds, specs, config = resolve(args)
    job_list = jobs(worlds, specs, args.trials, args.seed, config, args.map, keep_paths=plot is not None)
    labels = [s.label for s in specs]
    bar, on_done = None, None
    if show_progress(args):
        from tqdm import tqdm

        bar = tqdm(total=len(job_list), unit="run", desc="comparing", dynamic_ncols=True)

        def on_done(record):
            bar.update(1)

    executor, client = executor_for(args)
    t0 = time.perf_counter()
    try:
        records = compare(job_list, executor, on_done)
    finally:
        if bar is not None:
            bar.close()
        executor.shutdown(wait=True) if client is None else client.close()
    seconds = time.perf_counter() - t0
    rows = summarize(records, worlds, labels)
    if plot:
        from evaluation.compare_plot import save_comparison

        save_comparison(rows, records, worlds, labels, plot)
    where = f"Dask at {args.scheduler}" if args.scheduler else f"{args.workers or os.cpu_count()} local workers"
    if args.json:
        print_json({"results": [{k: v for k, v in r.items() if k != "runs_by_trial"} for r in rows],
                    "trials": args.trials, "seed": args.seed, "seconds": round(seconds, 2), "runs": len(records),
                    "workers": where, "config": config_dict(config), **provenance()})
        return
    print(f"{len(records)} runs ({len(labels)} architectures x {len(worlds)} worlds x {args.trials} trials, seeds "
          f"{args.seed}..{args.seed + args.trials - 1}) in {seconds:.0f} s on {where}")
    print_table(rows)
    if plot:
        print(f"plot written to {plot}")


def config_dict(config) -> dict:
    from dataclasses import asdict

    return asdict(config)


def print_table(rows) -> None:
    """The comparison as a table: success with its 95 % interval, mean time and path of the successes."""
    head = ("architecture", "world", "success", "95 % interval", "time s", "path m", "trapped", "collisions", "runs")
    lines = [head]
    for r in rows:
        lo, hi = r["success_ci95"]
        ok = round(r["success_rate"] * r["trials"])
        lines.append((r["architecture"], r["world"], f"{ok}/{r['trials']}", f"{lo:.2f}-{hi:.2f}",
                      "" if r["mean_time_s"] is None else f"{r['mean_time_s']:.1f}",
                      "" if r["mean_path_m"] is None else f"{r['mean_path_m']:.2f}",
                      str(r["trapped"]), str(r["collisions"]), r["runs_by_trial"]))
    widths = [max(len(str(line[i])) for line in lines) for i in range(len(head))]
    for line in lines:
        print("  ".join(str(v).ljust(w) for v, w in zip(line, widths)).rstrip())
