"""``ekm run``: drive the robot through a world with one architecture (thesis ch. 6.2; docs/design.md §5, §6)."""

from __future__ import annotations

from ekm.api.driving import SENSORS
from ekm.cli.args import (command, nonneg_float, nonneg_int, one_of, output_path, plot_path, positive_float, print_json,
                          show_progress)

ARCHITECTURE_HELP = ("ARCH[:k=v,...]: fusion, fields, samba, schema, or one an installed package adds, e.g. fields, "
                     "fields:form=thesis, fusion:beta=0.6,sensors=long; without parameters each runs its best "
                     "documented variant; ekm architectures lists them with their parameters")


LEARN_HELP = ("the map of an architecture that drives one (fusion, fields) goes on learning during the run "
              "(thesis ch. 4.3) at RULE's rates: error (default: faster while the map predicts badly), constant, "
              "either with parameters (constant:eta=0.1,sigma=1), or 0 (rate 0: the frozen run, bit for bit)")


def add_robot_options(p, learn_more: str = "") -> None:
    """``--robot`` and ``--learn``, shared by ``ekm run`` and ``ekm compare``."""
    p.add_argument("--robot", metavar="NAME|FILE",
                   help="the robot that drives: a named robot or a robot file (default khepera; ekm robots lists them)")
    p.add_argument("--learn", nargs="?", const="error", metavar="RULE", help=LEARN_HELP + learn_more)


def add_scenario_options(p) -> None:
    """The options of how a run goes, shared by ``ekm run`` and ``ekm compare``."""
    import argparse

    from ekm.api.planning import RULES

    p.add_argument("--recover", action=argparse.BooleanOptionalAction, default=True,
                   help="when trapped, add the sensed obstacle to the planner's map and replan (thesis 7.1.1); "
                        "--no-recover ends a run at its first trap (default: recover)")
    p.add_argument("--checkpoints", type=one_of(RULES), default="visible", metavar="{" + ",".join(RULES) + "}",
                   help="checkpoint rule: visible (consecutive checkpoints see each other with the robot's "
                        "clearance; default) or thesis (the greedy rule of ch. 3.2.3)")
    p.add_argument("--cell", type=positive_float, metavar="M",
                   help="planner's bitmap cell in metres (default 0.02; halved automatically where no route fits)")
    p.add_argument("--time-limit", type=positive_float, default=None, metavar="S",
                   help="simulated seconds before a run is given up (default: 10x the planned route at the robot's "
                        "top speed, at least 120)")


def add_parser(sub) -> None:
    p = command(sub, "run", "drive the robot through a world: planner and one architecture, one seed",
                ["ekm run --world concave-obstacle --architecture fields --plot run.png",
                 "ekm run --world my-lab.json --architecture fusion:beta=0.6,sensors=long --map polar.npz --json"],
                more="Architectures and their parameters: ekm architectures.")
    p.add_argument("--world", required=True, metavar="W", help="named world or world file")
    p.add_argument("--architecture", required=True, metavar="ARCH", help=ARCHITECTURE_HELP)
    p.add_argument("--sensors", type=one_of(SENSORS), metavar="{" + ",".join(SENSORS) + "}",
                   help="IR ring, overriding the architecture's (short: 8 Khepera sensors, 5 cm; long: 12, 17.5 cm)")
    add_scenario_options(p)
    add_robot_options(p)
    p.add_argument("--map", metavar="MAP.npz", help="indirect map from ekm train (default: the shipped map)")
    p.add_argument("--save-map", metavar="MAP.npz",
                   help="with --learn: save the map the run ended with (one trial); --map MAP.npz drives a later run "
                        "with it")
    p.add_argument("--trial", type=nonneg_int, metavar="K", help="which trial of the map drives (default: seed %% trials)")
    p.add_argument("--seed", type=nonneg_int, default=0, help="noise seed of the run (default 0)")
    p.add_argument("--engine", choices=("pymunk", "jax"), default="pymunk",
                   help="the robot's world: pymunk (default, the reference) or jax (the JAX engine; "
                        "its plot marks no checkpoints, traps or IR hits; docs/guide/jaxworld.md)")
    p.add_argument("--plot", metavar="PNG|SVG|PDF", help="draw the run to scale (Fig. 6.3-6.8)")
    p.add_argument("--gif", metavar="GIF", help="animate the run")
    p.add_argument("--maps-at", type=nonneg_float, metavar="T",
                   help="with --plot and samba: draw the Goto, Avoid and MAV action maps of the tick nearest T s "
                        "below the run (Riekki's Figs. 13-15)")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=run)


def run(args) -> None:
    """Drive the robot through a world with one architecture and report the outcome (docs/design.md §6;
    :func:`ekm.run`)."""
    from ekm.api.driving import run as drive
    from evaluation.motion import MEASURES
    from evaluation.pinning import pin_to_one_cpu

    pin_to_one_cpu()  # one run, one thread of work: one CPU for it (evaluation.pinning)
    plot = plot_path(args.plot, "--plot") if args.plot else None
    gif = output_path(args.gif, "--gif", ".gif") if args.gif else None
    save_map = output_path(args.save_map, "--save-map", ".npz") if args.save_map else None
    if save_map and args.learn is None:
        from ekm.errors import InputError

        raise InputError("--save-map: needs --learn (a frozen map ends the run as it began)")
    if args.maps_at is not None:
        from ekm.errors import InputError
        from robots.controllers.spec import parse_architecture

        name = parse_architecture(args.architecture).name
        if name != "samba":
            raise InputError(f"--maps-at: architecture {name} has no action maps (only samba has)")
        if not plot:
            raise InputError("--maps-at: needs --plot PNG to draw the maps on")
        if args.engine != "pymunk":
            raise InputError("--maps-at: draws a tick of the pymunk engine's run; drop --engine jax")
    outcome = drive(args.world, args.architecture, maps=args.map, trial=args.trial, sensors=args.sensors,
                    recover=args.recover, seed=args.seed, time_limit=args.time_limit, checkpoints=args.checkpoints,
                    cell=args.cell, robot=args.robot, learn=args.learn, progress=show_progress(args),
                    engine=args.engine)
    rec, spec = outcome.record, outcome.spec
    if plot and args.maps_at is not None:  # the same run again, recording the tick nearest T (a run is pure)
        from evaluation.actionmap_plot import record_tick, save_run_with_maps

        again, moment = record_tick(rec.world, spec, args.maps_at, seed=args.seed, config=outcome.config)
        again.map_source, again.trial = rec.map_source, rec.trial
        save_run_with_maps(again, moment, plot)
    elif plot:
        outcome.save_plot(plot)
    if gif:
        outcome.save_animation(gif, progress=show_progress(args))
    if save_map:
        outcome.save_map(save_map)
    if args.json:
        print_json(outcome.to_dict())
        return
    out = outcome.to_dict()
    status = outcome_status(out)
    drives = f", {out['map']}, trial {out['trial']}" if spec.uses_map else ""
    where = "" if args.engine == "pymunk" else f", {args.engine} engine"
    print(f"{rec.world.name}: {spec} on {out['robot']} (seed {args.seed}{drives}{where})")
    if out["map_robot"] is not None and out["map_robot"] != out["robot"]:
        print(f"  note: the map was trained on {out['map_robot']}, not on {out['robot']}")
    if out["learn"] is not None:
        print(f"  learning while driving ({out['learn']}): {out['updates']} updates of the map")
    print(f"  {status}: {out['ended']} after {out['time_s']:.1f} s, path {out['path_m']:.2f} m, "
          f"{out['collisions']} collisions, final distance {1000 * out['final_distance_m']:.1f} mm")
    print(f"  checkpoints reached {out['checkpoints_reached']}, replans {out['replans']}, recoveries {out['recoveries']}")
    print("  motion: " + ", ".join(f"{m.column} {out[m.key] * m.scale:.{m.digits}f}" for m in MEASURES
                                   if out[m.key] is not None))
    for path in (plot, gif, save_map):
        if path:
            print(f"  written to {path}")


def outcome_status(out: dict) -> str:
    """How a run ended, in the words of docs/design.md §5: it *reaches* the goal when it stops there without a
    collision; one that stopped there after a collision *arrived*, which is not reaching it."""
    if out["reached"]:
        return "REACHED the goal"
    if out["arrived"]:
        n = out["collisions"]
        return f"ARRIVED after {n} collision{'' if n == 1 else 's'}, so did not reach the goal"
    return "TRAPPED" if out["trapped"] else "did not reach the goal"
