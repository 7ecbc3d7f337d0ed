"""``ekm train``: train EKMs online with the ch. 6.1 protocol, save them, and test them as in
ch. 6.1 along the way (DESIGN §3, §6)."""

from __future__ import annotations

from ekm.cli.args import nonneg_int, output_path, positive_int, print_json, show_progress
from ekm.cli.summary import print_summary, summarize_test
from ekm.config import CHARTS
from ekm.errors import InputError


def add_parser(sub) -> None:
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
    p.set_defaults(func=run)


def run(args) -> None:
    """Train EKMs online with the ch. 6.1 protocol and save them (DESIGN §3, §6)."""
    import time

    import numpy as np

    from ekm.config import EKMConfig
    from ekm.mapfile import save_maps
    from robots.params import KHEPERA
    from robots.worldfile import load_world
    from training.online import TrainConfig
    from training.run import train

    out = output_path(args.out, "--out", ".npz")
    plot = output_path(args.plot, "--plot", ".png") if args.plot else None
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
        s = summarize_test(maps, cfg, tcfg.arena, args.eval_targets, args.test_seed)
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
    print_summary(final | {"trials": tcfg.trials, "targets": args.eval_targets}, "ch. 6.1 test after training")
    if plot:
        print(f"plot written to {plot}")
