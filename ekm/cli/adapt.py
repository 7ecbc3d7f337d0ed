"""``ekm adapt``: the adaptation experiment — a map trained on one robot, frozen, fine-tuned and trained from
scratch on others, tested as in ch. 6.1 against training steps (docs/design.md §10; :mod:`evaluation.adaptation`)."""

from __future__ import annotations

from ekm.cli.args import command, nonneg_int, plot_path, positive_int, print_json, show_progress


def add_parser(sub) -> None:
    from ekm.api.adapting import DEFAULT_ROBOTS

    p = command(sub, "adapt", "a map trained on one robot, on others: frozen, fine-tuned and trained from scratch, "
                "tested as in ch. 6.1 against training steps",
                ["ekm adapt --plot adapt.png", "ekm adapt --robots worn-wheel,weak-motor --steps 4000 --json",
                 "ekm adapt --robots my-robot.json --map my-map.npz --rate error"],
                more="The worlds, frozen against learning while driving: ekm compare --robot R [--learn] "
                     "(docs/reproduce/adaptation.md).")
    p.add_argument("--robots", default=DEFAULT_ROBOTS, metavar="R1,R2,...",
                   help=f"named robots or robot files (default {DEFAULT_ROBOTS})")
    p.add_argument("--map", metavar="MAP.npz", help="the map every robot starts from (default: the shipped signed-chart "
                   "map, trained on the Khepera)")
    p.add_argument("--steps", type=positive_int, default=10_000, help="fine-tuning steps (default 10000)")
    p.add_argument("--every", type=positive_int, default=500, metavar="STEPS",
                   help="fine-tuning steps between tests (default 500)")
    p.add_argument("--scratch-steps", type=positive_int, default=20_000, metavar="STEPS",
                   help="steps of the ch. 6.1 protocol trained from scratch (default 20000 of its 100000)")
    p.add_argument("--scratch-every", type=positive_int, default=500, metavar="STEPS",
                   help="steps between the from-scratch map's tests (default 500)")
    p.add_argument("--targets", type=positive_int, default=50, help="targets of each test (default 50)")
    p.add_argument("--seed", type=nonneg_int, default=1000, help="training seed (default 1000: never tuned on)")
    p.add_argument("--test-seed", type=nonneg_int, default=1000, help="seed of the test targets and noise (default 1000)")
    p.add_argument("--rate", metavar="RULE", help="the fine-tuning rule, as ekm train --rate spells it")
    p.add_argument("--plot", metavar="PNG|SVG|PDF", help="E, T(5), D(25) against steps, a row per robot")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=run)


def run(args) -> None:
    """Run the adaptation experiment (:func:`ekm.adapt`); print its table or JSON, draw its curves."""
    from ekm.api.adapting import adapt

    plot = plot_path(args.plot, "--plot") if args.plot else None
    table = adapt(args.robots, maps=args.map, steps=args.steps, every=args.every, scratch_steps=args.scratch_steps,
                  scratch_every=args.scratch_every, targets=args.targets, seed=args.seed, test_seed=args.test_seed,
                  rate=args.rate, progress=show_progress(args))
    if plot:
        table.save_plot(plot)
    if args.json:
        print_json(table.to_dict())
        return
    s = table.setup
    print(f"from {table.map['source']} (trained on {table.map['robot']}); fine-tuned {s['steps']} steps at "
          f"{s['rate']}; from scratch the first {s['scratch_steps']} steps of the ch. 6.1 protocol; tests of "
          f"{s['targets']} targets, seeds {s['seed']}/{s['test_seed']}; {table.seconds:.0f} s")
    head = ("robot", "frozen E mm", "T(5)", "D(25)", "fine-tuned E mm", "T(5)", "D(25)", "scratch E mm", "T(5)",
            "D(25)", "to E<=3mm: fine/scratch", "to scratch's T(5): fine/scratch")
    lines = [head]
    for r in table.rows:
        m = r["summary"]

        def cells(p):
            lo, hi = p["E_ci95"]
            return f"{p['E_mm']:.2f} ({lo:.2f}-{hi:.2f})", _num(p["T5"], 1), _num(p["D25"], 3)

        lines.append((r["robot"], *cells(m["frozen"]), *cells(m["fine_tuned"]), *cells(m["scratch"]),
                      _pair(m["steps_to_thesis_E"]), _pair(m["steps_to_scratch_T5"])))
    widths = [max(len(str(line[i])) for line in lines) for i in range(len(head))]
    for line in lines:
        print("  ".join(str(v).ljust(w) for v, w in zip(line, widths)).rstrip())
    if plot:
        print(f"plot written to {plot}")


def _num(x, digits):
    return "-" if x is None else f"{x:.{digits}f}"


def _pair(steps: dict) -> str:
    def one(x):
        return "never" if x is None else str(x)

    return f"{one(steps['fine_tuned'])} / {one(steps['scratch'])}"
