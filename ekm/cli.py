"""The ``ekm`` console script (DESIGN §6): the imperative shell around the packages.

Each sub-command imports what it needs inside its function, so ``ekm --help`` starts fast. Bad input
of any kind raises :class:`ekm.errors.InputError`; :func:`main` prints its one line on stderr and
exits with status 2 — never a traceback.
"""

from __future__ import annotations

import argparse
import json
import math
import sys

from ekm.config import CHARTS
from ekm.errors import InputError


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors (``ekm train: --steps: must be > 0``) and exit status 2."""

    def error(self, message):
        raise InputError(f"{self.prog}: {message}")


def _whole_number(text: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a whole number, got {text!r}") from None


def finite_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number, got {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"must be finite, got {text}")
    return value


def _signed(parse, *, strict: bool):
    """An argparse type: ``parse`` the text, then require > 0 (``strict``) or >= 0."""

    def check(text: str):
        value = parse(text)
        if value < 0 or (strict and value == 0):
            raise argparse.ArgumentTypeError(f"must be {'>' if strict else '>='} 0, got {text}")
        return value

    return check


positive_int = _signed(_whole_number, strict=True)
nonneg_int = _signed(_whole_number, strict=False)
positive_float = _signed(finite_float, strict=True)
nonneg_float = _signed(finite_float, strict=False)


def print_json(obj) -> None:
    """Write ``obj`` as the command's stable JSON output."""
    json.dump(obj, sys.stdout, indent=2, allow_nan=False)
    sys.stdout.write("\n")


def show_progress(args) -> bool:
    """Progress bars only on a terminal and never with ``--json``."""
    return not getattr(args, "json", False) and sys.stderr.isatty()


# ------------------------------------------------------------------------------------------- commands

def xy_point(text: str) -> tuple[float, float]:
    """``"X,Y"`` in metres → ``(x, y)``."""
    parts = text.split(",")
    try:
        if len(parts) != 2:
            raise argparse.ArgumentTypeError("")
        return finite_float(parts[0]), finite_float(parts[1])
    except argparse.ArgumentTypeError:
        raise argparse.ArgumentTypeError(f"must be X,Y in metres (e.g. 0.1,0.3), got {text!r}") from None


def cmd_plan(args) -> None:
    """Plan checkpoints through a world with slippery cells or a baseline decomposition (thesis ch. 3)."""
    import time

    from planner import DEFAULT_CELL, plan
    from robots.worldfile import load_world

    world = load_world(args.world)
    t0 = time.perf_counter()
    p = plan(world, args.start, args.goal, cell=args.cell or DEFAULT_CELL, method=args.method, t=args.at)
    seconds = time.perf_counter() - t0
    route = " -> ".join(map(str, p.route[:12])) + (f" -> ... ({len(p.route)} cells)" if len(p.route) > 12 else "")
    if args.plot:
        from planner.plot import save_plan

        title = f"{world.name} at t = {args.at:g} s: {p.method}, {p.cells} cells, {len(p.graph.edges)} arcs"
        save_plan(args.plot, p, world, args.at, title=title)
    if args.json:
        print_json({"method": p.method, "cells": p.cells, "graph_edges": len(p.graph.edges),
                    "path_cells": list(p.route), "checkpoints": p.checkpoints.round(6).tolist(),
                    "seconds": round(seconds, 6)})
        return
    ny, nx = p.bitmap.shape
    print(f"{world.name} at t = {args.at:g} s: {p.method} decomposition of a {nx} x {ny} bitmap "
          f"({p.cell:g} m cells, {int((p.bitmap == 0).sum())} free)")
    print(f"  {p.cells} cells, {len(p.graph.edges)} graph edges")
    print(f"  route: {route}")
    print(f"  start ({p.start[0]:.3f}, {p.start[1]:.3f})")
    k = len(p.checkpoints) - 1
    for i, (x, y) in enumerate(p.checkpoints[:-1][:10], 1):
        print(f"  checkpoint {i} ({x:.3f}, {y:.3f})")
    if k > 10:
        print(f"  ... {k - 10} more checkpoints (--json lists them all)")
    print(f"  goal ({p.goal[0]:.3f}, {p.goal[1]:.3f})")
    print(f"  checkpoint path {p.length:.3f} m, planned in {seconds:.3f} s")
    if args.plot:
        print(f"  plot written to {args.plot}")


def cmd_worlds(args) -> None:
    """List the named worlds, or validate world files (``--check``); draw them with ``--plot DIR``.

    Every file is validated before anything is drawn or printed, so a bad file (exit 2) leaves no output
    behind; each PNG is written atomically.
    """
    from robots.worldfile import load_world, named_worlds

    worlds = [load_world(p) for p in args.check] if args.check else [load_world(n) for n in named_worlds()]
    written = _plot_worlds(worlds, args.plot) if args.plot else []
    if args.json:
        print_json({"worlds": [w.counts() for w in worlds]})
        return
    rows = [("name", "size (m)", "walls", "obstacles", "unforeseen", "moving", "events", "goal")]
    for w in worlds:
        c = w.counts()
        rows.append((c["name"], f"{w.size[0]:g} x {w.size[1]:g}", c["walls"], c["obstacles"], c["unforeseen"],
                     c["moving"], len(w.events), "moving" if c["moving_goal"] else "fixed"))
    widths = [max(len(str(r[i])) for r in rows) for i in range(len(rows[0]))]
    for r in rows:
        print("  ".join(str(v).ljust(wd) if i < 2 else str(v).rjust(wd) for i, (v, wd) in enumerate(zip(r, widths))))
    for path in written:
        print(f"wrote {path}")


def _plot_worlds(worlds, directory: str) -> list:
    """Draw each world to ``directory/NAME.png`` (the directory is created); returns the paths written."""
    import re
    from pathlib import Path

    from robots.plot import plot_world, save_figure

    out = Path(directory)
    files = {}
    for w in worlds:
        name = re.sub(r"[^A-Za-z0-9._-]", "_", w.name) + ".png"
        if name in files:
            raise InputError(f"--plot {directory}: {files[name].source} and {w.source} would both be drawn to {name}")
        files[name] = w
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"--plot {directory}: cannot create the directory ({exc.strerror or exc})") from None
    written = []
    for name, w in files.items():
        try:
            written.append(save_figure(plot_world(w).figure, out / name))
        except OSError as exc:
            raise InputError(f"--plot {out / name}: cannot write ({exc.strerror or exc})") from None
    return written


def _output_path(text: str, option: str, suffix: str):
    """Check an output path before long work starts: not a directory, the right suffix, a directory
    that exists (it is created) and can be written."""
    import os
    from pathlib import Path

    path = Path(text)
    if path.is_dir():
        raise InputError(f"{option} {text}: is a directory, expected a {suffix} file")
    if path.suffix.lower() != suffix:
        raise InputError(f"{option} {text}: expected a file name ending in {suffix}")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"{option} {text}: cannot create its directory ({exc.strerror or exc})") from None
    if not os.access(path.parent, os.W_OK):
        raise InputError(f"{option} {text}: its directory is not writable")
    return path


def _test_summary(maps, cfg, arena, targets: int, seed: int) -> dict:
    """The ch. 6.1 test of stacked maps, summarised (E, P, T, D, capped)."""
    from evaluation.metrics import summarize
    from evaluation.protocol import evaluate

    return summarize(evaluate(maps, cfg, arena, targets=targets, seed=seed))


def _print_summary(s: dict, label: str) -> None:
    eps = list(s["P"])
    print(f"{label}: E = {s['E_mm']:.2f} mm over {s['trials']} trials x {s['targets']} targets "
          f"({s['capped']} hit the step cap before stopping)")
    print("  eps (mm)    " + "".join(f"{e:>9}" for e in eps))
    for key, fmt in (("P", "{:9.3f}"), ("T", "{:9.2f}"), ("D", "{:9.3f}")):
        print(f"  {key}(eps)      " + "".join(fmt.format(s[key][e]) if s[key][e] is not None else f"{'-':>9}"
                                          for e in eps))


def cmd_train(args) -> None:
    """Train EKMs online with the ch. 6.1 protocol and save them (DESIGN §3, §6)."""
    import time

    import numpy as np

    from ekm.config import EKMConfig
    from ekm.mapfile import save_maps
    from robots.params import KHEPERA
    from robots.worldfile import load_world
    from training.online import TrainConfig
    from training.run import train

    out = _output_path(args.out, "--out", ".npz")
    plot = _output_path(args.plot, "--plot", ".png") if args.plot else None
    world = load_world(args.world)
    if world.walls or world.obstacles or world.unforeseen or world.moving:
        raise InputError(f"--world {args.world}: training needs an obstacle-free world (thesis ch. 4.3)")
    try:
        cfg = EKMConfig(mapping=args.mapping, neurons=args.neurons, priority=args.priority, chart=args.chart)
        tcfg = TrainConfig(steps=args.steps, trials=args.trials, arena=tuple(world.size))
    except ValueError as exc:
        raise InputError(f"ekm train: {exc}") from None
    curve = []

    def on_eval(step, maps):
        s = _test_summary(maps, cfg, tcfg.arena, args.eval_targets, args.test_seed)
        curve.append({"step": step, "E_mm": s["E_mm"], "P": s["P"], "T": s["T"], "D": s["D"], "capped": s["capped"]})
        if show_progress(args):
            from tqdm import tqdm

            tqdm.write(f"  step {step:>7}: E = {s['E_mm']:7.2f} mm, P(25) = {s['P']['25']:.2f}")

    t0 = time.perf_counter()
    maps = train(cfg, tcfg, seed=args.seed, eval_every=args.eval_every, on_eval=on_eval, progress=show_progress(args))
    seconds = time.perf_counter() - t0
    meta = {"steps": tcfg.steps, "seed": args.seed, "world": world.name, "train": tcfg.to_dict(),
            "robot": KHEPERA.to_dict(), "test": {"targets": args.eval_targets, "seed": args.test_seed},
            "curve": curve, "seconds": seconds}
    save_maps(out, maps, cfg, meta)
    if plot:
        from evaluation.plots import save_figure_6_1_6_2

        save_figure_6_1_6_2([{"label": cfg.mapping, "curve": curve, "summary": curve[-1] | {"trials": tcfg.trials},
                              "w": np.asarray(maps.w[0])}], plot)
    if args.json:
        print_json({"mapping": cfg.mapping, "neurons": cfg.neurons, "steps": tcfg.steps, "trials": tcfg.trials,
                    "seconds": round(seconds, 3), "curve": curve, "out": str(out)})
        return
    final = curve[-1]
    print(f"trained {tcfg.trials} {cfg.mapping} {cfg.neurons}x{cfg.neurons} maps for {tcfg.steps} steps "
          f"in {seconds:.1f} s -> {out}")
    _print_summary(final | {"trials": tcfg.trials, "targets": args.eval_targets}, "ch. 6.1 test after training")
    if plot:
        print(f"plot written to {plot}")


def cmd_evaluate(args) -> None:
    """Run the ch. 6.1 test on saved maps (and draw Fig. 6.1/6.2 for them)."""
    from pathlib import Path

    import numpy as np

    from ekm.mapfile import load_maps

    plot = _output_path(args.plot, "--plot", ".png") if args.plot else None
    paths = _output_path(args.paths, "--paths", ".png") if args.paths else None
    loaded = [load_maps(path) for path in args.maps]
    results = []
    for path, saved in zip(args.maps, loaded):
        s = _test_summary(saved.ekm, saved.cfg, saved.arena, args.targets, args.seed)
        results.append({"file": path, "mapping": saved.cfg.mapping, **s})
    if plot:
        from evaluation.plots import save_figure_6_1_6_2

        save_figure_6_1_6_2([{"label": f"{r['mapping']} ({Path(r['file']).name})", "curve": list(saved.curve),
                              "summary": r, "w": np.asarray(saved.ekm.w[0])} for r, saved in zip(results, loaded)],
                            plot)
    if paths:
        _save_paths(args.maps, loaded, args.targets, args.seed, paths)
    if args.json:
        keys = ("E_mm", "P", "T", "D", "trials", "targets", "capped")
        print_json({k: results[0][k] for k in keys} if len(results) == 1
                   else {"maps": [{"file": r["file"], "mapping": r["mapping"], **{k: r[k] for k in keys}} for r in results]})
        return
    for r in results:
        _print_summary(r, f"{r['file']} ({r['mapping']})")
    for out in (plot, paths):
        if out:
            print(f"plot written to {out}")


def _save_paths(files, loaded, targets: int, seed: int, out) -> None:
    """``ekm evaluate --paths``: the first trial's paths in the same test, one panel per map."""
    from pathlib import Path

    from evaluation.metrics import summarize
    from evaluation.plots import save_paths_figure
    from evaluation.protocol import trace_paths

    panels = []
    for path, saved in zip(files, loaded):
        pts, start, xy, rec = trace_paths(saved.ekm, saved.cfg, saved.arena, targets=targets, seed=seed)
        panels.append({"label": f"{saved.cfg.mapping} ({Path(path).name}, trial 1)", "targets": pts, "start": start,
                       "xy": xy, "summary": summarize(rec)})
    save_paths_figure(panels, loaded[0].arena, out)


def cmd_bench(args) -> None:
    """Quick speed check: JAX training loop vs the NumPy reference (full study: benchmarks/)."""
    from training.bench import quick

    result = quick(args.mapping)
    if args.json:
        print_json(result)
        return
    print(f"online training, {result['mapping']} {result['neurons']}x{result['neurons']} map, "
          f"{result['trials']} trials, on {', '.join(result['devices'])} (jax {result['jax_version']})")
    print(f"  JAX (lax.scan + vmap): {result['jax_trial_steps_per_s']:>10,.0f} trial-steps/s "
          f"(first call with compilation {result['jax_first_call_s']:.1f} s)")
    print(f"  NumPy reference:       {result['numpy_trial_steps_per_s']:>10,.0f} trial-steps/s")
    print(f"  ratio {result['ratio']:.1f}x; 100,000 steps x 5 trials take about {result['protocol_estimate_s']:.0f} s")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="ekm", description="Extended Kohonen Maps for a Khepera-like robot (Low 2002).")
    from ekm import __version__

    parser.add_argument("--version", action="version", version=f"ekm {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

    p = sub.add_parser("worlds", help="list, check and draw worlds")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.add_argument("--plot", metavar="DIR", help="draw each world to DIR/NAME.png")
    p.add_argument("--check", metavar="FILE", nargs="+", help="validate world files (exit 2 on the first bad one)")
    p.set_defaults(func=cmd_worlds)

    p = sub.add_parser("plan", help="plan checkpoints through a world (slippery cells, quadtree or grid)")
    p.add_argument("--world", required=True, metavar="W", help="named world or world file")
    p.add_argument("--start", type=xy_point, metavar="X,Y", help="start in metres (default: the world's)")
    p.add_argument("--goal", type=xy_point, metavar="X,Y", help="goal in metres (default: the world's)")
    p.add_argument("--cell", type=positive_float, metavar="M", help="bitmap cell size in metres (default 0.02)")
    p.add_argument("--method", choices=("slippery", "quadtree", "grid"), default="slippery",
                   help="cell decomposition (default slippery)")
    p.add_argument("--at", type=nonneg_float, default=0.0, metavar="SECONDS",
                   help="plan on the map known at this time (after the known events so far; default 0)")
    p.add_argument("--plot", metavar="PNG", help="draw cells, graph, route and checkpoints to PNG")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=cmd_plan)
    p = sub.add_parser("train", help="train EKMs online (thesis ch. 4.3) and test them as in ch. 6.1")
    p.add_argument("--mapping", choices=("direct", "indirect"), required=True, help="direct (ch. 4.1) or indirect (ch. 4.2)")
    p.add_argument("--neurons", type=positive_int, default=15, metavar="N", help="N x N lattice (default 15)")
    p.add_argument("--priority", type=positive_int, default=None, metavar="K",
                   help="|A(alpha)| of Eq. 4.4: the K neurons of most similar angle compete (default N)")
    p.add_argument("--chart", choices=CHARTS, default=CHARTS[0],
                   help="coordinates of the linear model c = M u (Eq. 4.1): signed (default; polar ahead, "
                        "measured from the back with negative distance behind) or polar (as the thesis writes it)")
    p.add_argument("--steps", type=positive_int, default=100_000, help="training steps of 1.024 s (default 100000)")
    p.add_argument("--trials", type=positive_int, default=5, help="independent trials (default 5)")
    p.add_argument("--seed", type=nonneg_int, default=0, help="training seed (default 0)")
    p.add_argument("--eval-every", type=positive_int, default=10_000, metavar="STEPS",
                   help="run the ch. 6.1 test every STEPS steps (default 10000)")
    p.add_argument("--eval-targets", type=positive_int, default=50, metavar="N", help="test targets (default 50)")
    p.add_argument("--test-seed", type=nonneg_int, default=0, help="seed of the test targets (default 0)")
    p.add_argument("--world", default="open-arena", help="obstacle-free world whose arena is used (default open-arena)")
    p.add_argument("--out", required=True, metavar="MAP.npz", help="where to save the trained maps")
    p.add_argument("--plot", metavar="PNG", help="draw Fig. 6.1/6.2 for the trained maps")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=cmd_train)

    p = sub.add_parser("evaluate", help="run the ch. 6.1 positioning test on saved maps")
    p.add_argument("maps", nargs="+", metavar="MAP.npz", help="map file(s) from ekm train; several share one plot")
    p.add_argument("--targets", type=positive_int, default=50, help="test targets (default 50)")
    p.add_argument("--seed", type=nonneg_int, default=0, help="seed of the test targets and noise (default 0)")
    p.add_argument("--plot", metavar="PNG", help="draw Fig. 6.1/6.2 with all maps on the same axes")
    p.add_argument("--paths", metavar="PNG", help="draw each map's paths through the first 10 test targets")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=cmd_evaluate)

    p = sub.add_parser("bench", help="quick speed check of the training loop (JAX vs NumPy)")
    p.add_argument("--mapping", choices=("direct", "indirect"), default="indirect")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=cmd_bench)

    return parser


def main(argv=None) -> int:
    try:
        args = build_parser().parse_args(argv)
        args.func(args)
    except InputError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return InputError.exit_status
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # e.g. `ekm plan --json | head`: the reader left, nothing to report
        import os

        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 141
    return 0


if __name__ == "__main__":
    sys.exit(main())
