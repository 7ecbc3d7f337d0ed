"""``ekm compare``: every architecture × world × trial through the scenario runner, in parallel, with
95 % intervals (docs/design.md §6; :mod:`evaluation.compare`)."""

from __future__ import annotations

from ekm.cli.args import (add_batch_options, command, in_this_process, nonneg_int, plot_path, positive_int,
                          print_columns, print_json, print_written, show_progress)
from ekm.cli.run import add_robot_options, add_scenario_options


def add_parser(sub) -> None:
    p = command(sub, "compare", "compare architectures over worlds and seeds, with 95 % intervals (in parallel; on Dask "
                "with --scheduler)",
                ["ekm compare --worlds three-rooms,concave-obstacle --architectures fusion,fields --trials 20",
                 "ekm compare --suite corridor:20,maze:20 --trials 1 --out suite.jsonl --plot suite.png",
                 "ekm compare --from suite.jsonl --json",
                 "ekm compare --worlds three-rooms-static,open-arena --architectures fields,schema,damn,subsumption "
                 "--motion"],
                more="Architectures and their parameters: ekm architectures. Results files, resume, workers that "
                     "die: docs/guide/comparing.md.")
    p.add_argument("--worlds", default="", metavar="W1,W2,...",
                   help="named worlds, world files or generated worlds (maze:7), comma-separated")
    p.add_argument("--suite", metavar="FAMILY:COUNT,...",
                   help="generated worlds, COUNT of each family (ekm worlds --help lists the families), with seeds "
                        "from --world-seed; the table then reports by family")
    p.add_argument("--world-seed", type=nonneg_int, default=1000, metavar="N",
                   help="first seed of the --suite worlds (default 1000: the test seeds, never tuned on)")
    p.add_argument("--architectures", default="fusion,fields,samba,schema", metavar="A1[:k=v,...],A2,...",
                   help="as ekm run spells them, comma-separated; a k=v after a comma continues the architecture "
                        "before it (fusion:sensors=long,beta=0.8,fields); default fusion,fields,samba,schema; "
                        "ekm architectures lists them all with their parameters")
    p.add_argument("--trials", type=positive_int, default=10, help="runs per architecture and world (default 10)")
    p.add_argument("--seed", type=nonneg_int, default=0,
                   help="trial i runs with seed SEED + i for every architecture and world (default 0)")
    p.add_argument("--map", metavar="MAP.npz", help="map for the EKM architectures (default: their shipped maps)")
    p.add_argument("--engine", choices=("pymunk", "jax"), default="pymunk",
                   help="the robot's world: pymunk (default, the reference) or jax (each architecture's runs in one "
                        "batch in this process; docs/guide/jaxworld.md)")
    add_scenario_options(p)
    add_robot_options(p, "; every run starts from the same map")
    add_batch_options(p, "run", "finish the comparison of this results file (the same arguments as the one that made "
                                "it): only the missing runs are made")
    p.add_argument("--from", dest="from_results", metavar="RESULTS.jsonl",
                   help="no runs: the table (and --plot, --json) of a finished results file")
    p.add_argument("--motion", action="store_true",
                   help="also print each architecture's motion over all its runs (smoothness, hesitation, efficiency, "
                        "precision; mean ± 95 %% interval) with its response encoding")
    p.add_argument("--plot", metavar="PNG|SVG|PDF", help="success rates with their intervals, and one path per cell")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=run)


def run(args) -> None:
    """Compare architectures over worlds and trials (:func:`ekm.compare`); print the table or the JSON, draw
    the plot."""
    from ekm.api.comparing import compare, load_comparison
    from ekm.errors import InputError

    plot = plot_path(args.plot, "--plot") if args.plot else None
    if args.from_results:
        if args.out or args.resume:
            raise InputError("ekm compare: --from makes no runs; drop --out and --resume")
        table = load_comparison(args.from_results)
    else:
        in_this_process(args)
        table = compare(args.worlds, args.architectures, suite=args.suite, world_seed=args.world_seed,
                        trials=args.trials, seed=args.seed, maps=args.map, recover=args.recover,
                        time_limit=args.time_limit, checkpoints=args.checkpoints, cell=args.cell,
                        workers=args.workers, scheduler=args.scheduler, out=args.out, resume=args.resume,
                        robot=args.robot, learn=args.learn, engine=args.engine, progress=show_progress(args))
    if plot:
        table.save_plot(plot)
    if args.json:
        print_json(table.to_dict())
        return
    failed = sum("failed" in r for r in table.records)
    print(f"{len(table.records)} runs ({len(table.labels)} architectures x {len(table.worlds)} worlds x {table.trials} "
          f"trials, seeds {table.seed}..{table.seed + table.trials - 1}) in {table.seconds:.0f} s on {table.workers}"
          + (f"; {failed} failed (the reasons: --json, or the results file)" if failed else ""))
    print_robot(table)
    if table.families:
        print_families(table.families)
        named = [r for r in table.rows if not any(r["world"] == g["given"] for g in table.records if g.get("family"))]
        if named:
            print_table(named)
    else:
        print_table(table.rows)
    if args.motion:
        print()
        print_motion(table.overall)
    print_written(args, plot)  # --from takes neither --out nor --resume


def print_robot(table) -> None:
    """The robot the runs drove, the robots their maps were trained on when that is another, and the learning."""
    robots = sorted({r.get("robot") or "khepera" for r in table.records})
    trained = sorted({r["map_robot"] for r in table.records if r.get("map_robot")} - set(robots))
    line = f"robot: {', '.join(robots)}"
    if trained:
        line += f" (the maps were trained on {', '.join(trained)})"
    if table.learn:
        line += f"; the maps learn while driving ({table.learn})"
    print(line)


def print_families(rows) -> None:
    """The comparison by family of generated worlds: success with its 95 % interval over all their runs."""
    head = ("family", "architecture", "worlds", "success", "95 % interval", "BARN", "time s", "trapped", "collisions",
            "failed")
    print_columns([head] + [(r["family"], r["architecture"], str(r["worlds"]), *_success(r), _barn(r),
                             _mean(r["mean_time_s"], 1), str(r["trapped"]), str(r["collisions"]), str(r["failed"]))
                            for r in rows])


def _barn(r) -> str:
    """The row's mean BARN score ± the half-width of its 95 % interval (:func:`evaluation.motion.barn_score`)."""
    score = r.get("motion", {}).get("barn_score") or {}
    if score.get("mean") is None:
        return ""
    lo, hi = score["ci95"]
    return f"{score['mean']:.3f}±{(hi - lo) / 2:.3f}"


def _success(r) -> tuple[str, str]:
    """``("k/n", "lo-hi")`` of a summary row: runs that reached the goal of the ``n`` that were made, and the 95 %
    interval; ``("failed", "")`` when no run could be made (the reasons: ``--json``)."""
    if r["success_rate"] is None:
        return "failed", ""
    lo, hi = r["success_ci95"]
    made = r["trials"] - r["failed"]
    return f"{round(r['success_rate'] * made)}/{made}", f"{lo:.2f}-{hi:.2f}"


def _mean(value, digits: int) -> str:
    return "" if value is None else f"{value:.{digits}f}"


def print_table(rows) -> None:
    """The comparison as a table: success with its 95 % interval, mean time and path of the successes."""
    head = ("architecture", "world", "success", "95 % interval", "BARN", "time s", "path m", "trapped", "collisions",
            "runs")
    print_columns([head] + [(r["architecture"], r["world"], *_success(r), _barn(r), _mean(r["mean_time_s"], 1),
                             _mean(r["mean_path_m"], 2), str(r["trapped"]), str(r["collisions"]), r["runs_by_trial"])
                            for r in rows])


def print_motion(rows) -> None:
    """Each architecture over all its runs (:func:`evaluation.compare.by_architecture`): its response encoding,
    success, and each motion measure (:data:`evaluation.motion.MEASURES`) as mean ± the half-width of its 95 %
    interval."""
    from evaluation.motion import MEASURES
    from robots.controllers.spec import ARCHITECTURES

    known = ARCHITECTURES.all()

    def encoding(label: str) -> str:
        arch = known.get(label.split(":")[0])
        return (arch.encoding if arch else None) or "-"

    def cell(m, scale, digits):
        if m["mean"] is None:
            return ""
        half = (m["ci95"][1] - m["ci95"][0]) / 2 * scale
        return f"{m['mean'] * scale:.{digits}f} ±{half:.{digits}f}"

    head = ("architecture", "encoding", "runs", "success") + tuple(m.column for m in MEASURES)
    print_columns([head] + [(r["architecture"], encoding(r["architecture"]), str(r["trials"]), _success(r)[0],
                      *(cell(r["motion"][m.key], m.scale, m.digits) for m in MEASURES)) for r in rows])
