"""``ekm train``: train EKMs online with the ch. 6.1 protocol, save them, and test them as in
ch. 6.1 along the way (docs/design.md §3, §6); checkpoints at every test, ``--resume`` after an interruption."""

from __future__ import annotations

from ekm.cli.args import command, nonneg_int, one_of, plot_path, positive_int, print_json, show_progress
from ekm.cli.summary import print_summary
from ekm.config import CHARTS
from ekm.errors import InputError

#: The settings of a run (the keywords of :func:`ekm.train`, which holds their defaults): a checkpoint
#: carries them, and ``--resume`` takes them from there.
SETTINGS = ("mapping", "neurons", "priority", "chart", "steps", "trials", "seed", "eval_every", "eval_targets",
            "test_seed", "world", "out", "robot", "init", "rate")


def add_parser(sub) -> None:
    p = command(sub, "train", "train EKMs online (thesis ch. 4.3) and test them as in ch. 6.1",
                ["ekm train --mapping indirect --out indirect.npz --plot indirect.png",
                 "ekm train --mapping indirect --chart polar --out polar.npz   # the map command fusion drives",
                 "ekm train --init ekm/data/indirect-signed.npz --robot worn-wheel --out worn.npz   # fine-tune",
                 "ekm train --resume indirect.checkpoint.npz                    # after Ctrl-C"],
                usage="ekm train (--mapping {direct,indirect} | --init MAP.npz) --out MAP.npz [options] | "
                      "--resume CKPT.npz")
    p.add_argument("--mapping", type=one_of(("direct", "indirect")), metavar="{direct,indirect}",
                   help="direct (ch. 4.1) or indirect (ch. 4.2); required")
    p.add_argument("--neurons", type=positive_int, metavar="N", help="N x N lattice (default 15)")
    p.add_argument("--priority", type=positive_int, metavar="K",
                   help="|A(alpha)| of Eq. 4.4: the K neurons of most similar angle compete (default N)")
    p.add_argument("--chart", type=one_of(CHARTS), metavar="{" + ",".join(CHARTS) + "}",
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
    p.add_argument("--robot", metavar="NAME|FILE",
                   help="the robot trained and tested on: a named robot or a robot file (default khepera; ekm robots)")
    p.add_argument("--init", metavar="MAP.npz",
                   help="go on training these maps instead of starting from scratch (fine-tuning: their lattice, "
                        "chart and trials are kept; --steps defaults to 10000, --eval-every to 1000)")
    p.add_argument("--rate", metavar="RULE",
                   help="with --init: the fine-tuning rule, error (default: faster while the map predicts badly) or "
                        "constant, with parameters as ekm run --learn spells them (constant:eta=0.005,sigma=0.3: "
                        "the end of training's schedules)")
    p.add_argument("--out", metavar="MAP.npz", help="where to save the trained maps; required")
    p.add_argument("--checkpoint", metavar="CKPT.npz",
                   help="where to keep the checkpoint while training (default: OUT with .checkpoint.npz; "
                        "removed when the maps are saved)")
    p.add_argument("--resume", metavar="CKPT.npz",
                   help="continue an interrupted run from its checkpoint, with the settings it was started with")
    p.add_argument("--plot", metavar="PNG|SVG|PDF", help="draw Fig. 6.1/6.2 for the trained maps")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=run)


def run(args) -> None:
    """Train EKMs online with the ch. 6.1 protocol and save them (docs/design.md §3, §6): :func:`ekm.train`, or
    :func:`ekm.resume` with ``--resume``."""
    from ekm.api.training import resume, train

    given = {name: getattr(args, name) for name in SETTINGS if getattr(args, name) is not None}
    plot = plot_path(args.plot, "--plot") if args.plot else None
    if args.resume:
        extra = [f"--{name.replace('_', '-')}" for name in given if name != "out"]
        if extra:
            raise InputError(f"--resume continues the run with the settings it was started with; drop {', '.join(extra)}")
        maps = resume(args.resume, out=args.out, checkpoint_to=args.checkpoint, progress=show_progress(args))
    else:
        missing = [f"--{name}" for name in ("mapping", "out") if name not in given
                   and not (name == "mapping" and "init" in given)]
        if missing:
            raise InputError(f"ekm train: the following arguments are required: {', '.join(missing)}")
        maps = train(**given, checkpoint=args.checkpoint, progress=show_progress(args))
    if plot:
        maps.save_plot(plot)
    if args.json:
        print_json(maps.to_dict())
        return
    d = maps.to_dict()
    resumed = f" (resumed at step {maps.meta['resumed_at']})" if maps.meta.get("resumed_at") else ""
    robot = maps.meta["robot"]["name"]
    start = ""
    if maps.meta.get("init"):
        start = f" from {maps.meta['init']['file']} (trained on {maps.meta['init']['robot']}; {maps.meta['init']['rate']})"
    verb = "fine-tuned" if start else "trained"
    print(f"{verb} {d['trials']} {d['mapping']} {d['neurons']}x{d['neurons']} maps on {robot} for {d['steps']} steps"
          f"{start}{resumed} in {maps.meta['seconds']:.1f} s -> {maps.path}")
    print_summary(maps.curve[-1] | {"trials": d["trials"], "targets": d["test"]["targets"]}, "ch. 6.1 test after training")
    if plot:
        print(f"plot written to {plot}")
