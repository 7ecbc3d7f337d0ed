"""``ekm train``: train EKMs online with the ch. 6.1 protocol, save them, and test them as in
ch. 6.1 along the way (DESIGN §3, §6); checkpoints at every test, ``--resume`` after an interruption."""

from __future__ import annotations

from ekm.cli.args import nonneg_int, output_path, positive_int, print_json, provenance, show_progress
from ekm.cli.summary import print_summary, summarize_test
from ekm.config import CHARTS
from ekm.errors import InputError, Interrupted

#: The settings of a run: its map, its protocol, its seeds and where it writes — a checkpoint carries
#: them, and ``--resume`` takes them from there. ``(option, default)``; None = required.
SETTINGS = (("mapping", None), ("neurons", 15), ("priority", None), ("chart", CHARTS[0]), ("steps", 100_000),
            ("trials", 5), ("seed", 0), ("eval_every", 10_000), ("eval_targets", 50), ("test_seed", 0),
            ("world", "open-arena"), ("out", None))


def add_parser(sub) -> None:
    p = sub.add_parser("train", help="train EKMs online (thesis ch. 4.3) and test them as in ch. 6.1")
    p.add_argument("--mapping", choices=("direct", "indirect"), help="direct (ch. 4.1) or indirect (ch. 4.2); required")
    p.add_argument("--neurons", type=positive_int, metavar="N", help="N x N lattice (default 15)")
    p.add_argument("--priority", type=positive_int, metavar="K",
                   help="|A(alpha)| of Eq. 4.4: the K neurons of most similar angle compete (default N)")
    p.add_argument("--chart", choices=CHARTS,
                   help="coordinates of the linear model c = M u (Eq. 4.1): signed (default; polar ahead, "
                        "measured from the back with negative distance behind) or polar (as the thesis writes it)")
    p.add_argument("--steps", type=positive_int, help="training steps of 1.024 s (default 100000)")
    p.add_argument("--trials", type=positive_int, help="independent trials (default 5)")
    p.add_argument("--seed", type=nonneg_int, help="training seed (default 0)")
    p.add_argument("--eval-every", type=positive_int, metavar="STEPS",
                   help="run the ch. 6.1 test (and write a checkpoint) every STEPS steps (default 10000)")
    p.add_argument("--eval-targets", type=positive_int, metavar="N", help="test targets (default 50)")
    p.add_argument("--test-seed", type=nonneg_int, help="seed of the test targets (default 0)")
    p.add_argument("--world", help="obstacle-free world whose arena is used (default open-arena)")
    p.add_argument("--out", metavar="MAP.npz", help="where to save the trained maps; required")
    p.add_argument("--checkpoint", metavar="CKPT.npz",
                   help="where to keep the checkpoint while training (default: OUT with .checkpoint.npz; "
                        "removed when the maps are saved)")
    p.add_argument("--resume", metavar="CKPT.npz",
                   help="continue an interrupted run from its checkpoint, with the settings it was started with")
    p.add_argument("--plot", metavar="PNG", help="draw Fig. 6.1/6.2 for the trained maps")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=run)


def settings_of(args) -> dict:
    """The run's settings from the command line (a new run) — every required one given, defaults filled in."""
    given = {name: getattr(args, name) for name, _ in SETTINGS}
    missing = [f"--{name.replace('_', '-')}" for name, default in SETTINGS if default is None and given[name] is None
               and name != "priority"]
    if missing:
        raise InputError(f"ekm train: the following arguments are required: {', '.join(missing)}")
    return {name: default if given[name] is None else given[name] for name, default in SETTINGS}


def configs(settings: dict):
    """``(cfg, tcfg, world)`` of a run's settings; bad values are :class:`InputError`."""
    from ekm.config import EKMConfig
    from robots.worldfile import load_world
    from training.online import TrainConfig

    world = load_world(settings["world"])
    if world.walls or world.obstacles or world.unforeseen or world.moving:
        raise InputError(f"--world {settings['world']}: training needs an obstacle-free world (thesis ch. 4.3)")
    try:
        cfg = EKMConfig(mapping=settings["mapping"], neurons=settings["neurons"], priority=settings["priority"],
                        chart=settings["chart"])
        tcfg = TrainConfig(steps=settings["steps"], trials=settings["trials"], arena=tuple(world.size))
    except (TypeError, ValueError) as exc:
        raise InputError(f"ekm train: {exc}") from None
    return cfg, tcfg, world


class _Template:
    """The fresh carry of a run's settings: what a checkpoint's arrays must look like."""

    def __init__(self, settings: dict):
        from training.run import fresh

        cfg, tcfg, _ = configs(settings)
        self.carry, key = fresh(cfg, tcfg, int(settings["seed"]))
        self.key_shape = tuple(key.shape)
        self.settings_steps = tcfg.steps


def default_checkpoint(out) -> "Path":
    """``indirect.npz`` -> ``indirect.checkpoint.npz``, next to it."""
    from pathlib import Path

    out = Path(out)
    return out.with_name(out.name[: -len(out.suffix)] + ".checkpoint.npz")


def run(args) -> None:
    """Train EKMs online with the ch. 6.1 protocol and save them (DESIGN §3, §6)."""
    import time

    import numpy as np

    from ekm.mapfile import save_maps
    from robots.params import KHEPERA
    from training.checkpoint import Checkpoint, load_checkpoint, save_checkpoint, saved_step
    from training.run import train

    if args.resume:
        extra = [f"--{name.replace('_', '-')}" for name, _ in SETTINGS if name != "out" and getattr(args, name) is not None]
        if extra:
            raise InputError(f"--resume continues the run with the settings it was started with; drop {', '.join(extra)}")
        ckpt = load_checkpoint(args.resume, _Template)
        settings = ckpt.settings | ({"out": args.out} if args.out else {})
        resume, curve = (ckpt.done, ckpt.trainees, ckpt.key_run), list(ckpt.curve)
        checkpoint = output_path(args.checkpoint or args.resume, "--checkpoint", ".npz")
    else:
        settings = settings_of(args)
        resume, curve = None, []
    out = output_path(settings["out"], "--out", ".npz")
    if not args.resume:
        checkpoint = output_path(args.checkpoint or str(default_checkpoint(out)), "--checkpoint", ".npz")
    if checkpoint.resolve() == out.resolve():
        raise InputError(f"--checkpoint {checkpoint}: must differ from --out")
    plot = output_path(args.plot, "--plot", ".png") if args.plot else None
    cfg, tcfg, world = configs(settings)

    def on_eval(step, maps):
        s = summarize_test(maps, cfg, tcfg.arena, settings["eval_targets"], settings["test_seed"])
        curve.append({"step": step, "E_mm": s["E_mm"], "P": s["P"], "T": s["T"], "D": s["D"], "capped": s["capped"]})
        if show_progress(args):
            from tqdm import tqdm

            tqdm.write(f"  step {step:>7}: E = {s['E_mm']:7.2f} mm, P(25) = {s['P']['25']:.2f}")

    def on_checkpoint(step, trainees, key_run):
        if step < tcfg.steps:  # the last one is the map file itself
            save_checkpoint(checkpoint, Checkpoint(trainees, step, np.asarray(key_run), curve, settings))

    t0 = time.perf_counter()
    try:
        maps = train(cfg, tcfg, seed=int(settings["seed"]), eval_every=settings["eval_every"], on_eval=on_eval,
                     on_checkpoint=on_checkpoint, resume=resume, progress=show_progress(args))
    except KeyboardInterrupt:
        step = saved_step(checkpoint)  # what the file holds: a save cut short leaves the one before
        if step is None:
            raise Interrupted("training stopped before its first checkpoint; nothing was written") from None
        raise Interrupted(f"training stopped; the checkpoint at step {step} is {checkpoint}; "
                          f"resume with: ekm train --resume {checkpoint}") from None
    seconds = time.perf_counter() - t0
    meta = {"steps": tcfg.steps, "seed": settings["seed"], "world": world.name, "train": tcfg.to_dict(),
            "robot": KHEPERA.to_dict(), "test": {"targets": settings["eval_targets"], "seed": settings["test_seed"]},
            "curve": curve, "seconds": seconds}
    save_maps(out, maps, cfg, meta)
    checkpoint.unlink(missing_ok=True)
    if plot:
        from evaluation.plots import save_figure_6_1_6_2

        save_figure_6_1_6_2([{"label": cfg.mapping, "curve": curve, "summary": curve[-1] | {"trials": tcfg.trials},
                              "w": np.asarray(maps.w[0])}], plot)
    if args.json:
        print_json({"mapping": cfg.mapping, "neurons": cfg.neurons, "steps": tcfg.steps, "trials": tcfg.trials,
                    "seconds": round(seconds, 3), "curve": curve, "out": str(out), "seed": settings["seed"],
                    "world": world.name, "ekm": cfg.to_dict(), "train": tcfg.to_dict(),
                    "test": {"targets": settings["eval_targets"], "seed": settings["test_seed"]}, **provenance()})
        return
    final = curve[-1]
    resumed = f" (resumed at step {resume[0]})" if resume else ""
    print(f"trained {tcfg.trials} {cfg.mapping} {cfg.neurons}x{cfg.neurons} maps for {tcfg.steps} steps{resumed} "
          f"in {seconds:.1f} s -> {out}")
    print_summary(final | {"trials": tcfg.trials, "targets": settings["eval_targets"]}, "ch. 6.1 test after training")
    if plot:
        print(f"plot written to {plot}")
