"""``ekm evaluate``: run the ch. 6.1 positioning test on saved maps (and draw Fig. 6.1/6.2 and their
paths for them)."""

from __future__ import annotations

from ekm.cli.args import command, nonneg_int, plot_path, positive_int, print_json
from ekm.cli.summary import print_summary


def add_parser(sub) -> None:
    p = command(sub, "evaluate", "run the ch. 6.1 positioning test (E, P, T, D) on saved maps",
                ["ekm evaluate indirect.npz direct.npz --plot fig6.png", "ekm evaluate indirect.npz --targets 200 --json"])
    p.add_argument("maps", nargs="+", metavar="MAP.npz", help="map file(s) from ekm train; several share one plot")
    p.add_argument("--targets", type=positive_int, default=50, help="test targets (default 50)")
    p.add_argument("--seed", type=nonneg_int, default=0, help="seed of the test targets and noise (default 0)")
    p.add_argument("--robot", metavar="NAME|FILE",
                   help="the robot the test drives: a named robot or a robot file (default khepera; ekm robots)")
    p.add_argument("--plot", metavar="PNG|SVG|PDF", help="draw Fig. 6.1/6.2 with all maps on the same axes")
    p.add_argument("--paths", metavar="PNG|SVG|PDF", help="draw each map's paths through the first 10 test targets")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=run)


def run(args) -> None:
    """Run the ch. 6.1 test on saved maps (:func:`ekm.evaluate`; and draw Fig. 6.1/6.2 for them)."""
    from ekm.api.evaluation import Evaluation, evaluate

    plot = plot_path(args.plot, "--plot") if args.plot else None
    paths = plot_path(args.paths, "--paths") if args.paths else None
    result = evaluate(args.maps if len(args.maps) > 1 else args.maps[0], targets=args.targets, seed=args.seed,
                      robot=args.robot)
    every = result if isinstance(result, Evaluation) else Evaluation((result,))
    if plot:
        every.save_plot(plot)
    if paths:
        every.save_paths(paths)
    if args.json:
        print_json(result.to_dict())
        return
    for m in every.items:
        trained = "" if m.map_robot == m.robot else f"; trained on {m.map_robot}"
        print_summary(m.to_dict(), f"{m.file} ({m.mapping}) on {m.robot}{trained}")
    for out in (plot, paths):
        if out:
            print(f"plot written to {out}")
