"""``ekm worlds``: list the named worlds, or validate world files (``--check``); draw them with
``--plot DIR``; generate a benchmark world (``--generate FAMILY --seed N --out FILE``)."""

from __future__ import annotations

from ekm.cli.args import command, finite_float, nonneg_int, print_json


def add_parser(sub) -> None:
    p = command(sub, "worlds", "list the named worlds, check world files, draw them, or generate a world of a "
                "benchmark family",
                ["ekm worlds", "ekm worlds --show three-rooms > my-lab.json   # a template to edit",
                 "ekm worlds --check my-lab.json --plot my-lab.png",
                 "ekm worlds --generate maze --seed 7 --out maze7.json"],
                more="A generated world's family is one of ekm families (--generate FAMILY --seed N [--difficulty D] "
                     "--out FILE);\nthe world's name, FAMILY:SEED or FAMILY:SEED:D, is also a --world everywhere.")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.add_argument("--plot", metavar="DIR|PLOT",
                   help="draw each world to DIR/NAME.png, or one world to PLOT (.png, .svg or .pdf; with --generate: "
                        "the generated world)")
    p.add_argument("--check", metavar="FILE", nargs="+", help="validate world files (exit 2 on the first bad one)")
    p.add_argument("--show", metavar="WORLD",
                   help="print a world's file (a named world, a file or FAMILY:SEED): a template for your own")
    p.add_argument("--generate", metavar="FAMILY",
                   help="generate a world of FAMILY (ekm families lists them); needs --seed and --out")
    p.add_argument("--seed", metavar="N", type=nonneg_int, help="the generated world's seed (whole number >= 0)")
    p.add_argument("--difficulty", metavar="D", type=finite_float,
                   help="its difficulty in [0, 1] (default: drawn from the seed)")
    p.add_argument("--out", metavar="FILE", help="write the generated world to FILE (.json)")
    p.set_defaults(func=run)


def run(args) -> None:
    """List the named worlds, or validate world files (``--check``); draw them with ``--plot DIR``
    (:func:`ekm.worlds`); or generate a world (``--generate``, :func:`ekm.generate`).

    Every file is validated before anything is drawn or printed, so a bad file (exit 2) leaves no output
    behind; each PNG is written atomically.
    """
    if args.generate is not None:
        generate(args)
        return
    from ekm.errors import InputError

    if args.show is not None:
        if args.check or args.plot or args.json:
            raise InputError("ekm worlds: --show prints one world's file; drop --check, --plot and --json")
        from ekm.api.worlds import world
        from robots.worldfile import world_json

        print(world_json(world(args.show)), end="")
        return

    for option in ("seed", "difficulty", "out"):
        if getattr(args, option) is not None:
            raise InputError(f"ekm worlds: argument --{option}: only with --generate")
    from ekm.api.worlds import worlds as list_worlds

    result = list_worlds(check=args.check)
    written = result.save_plots(args.plot) if args.plot else []
    if args.json:
        print_json(result.to_dict())
        return
    rows = [("name", "size (m)", "walls", "obstacles", "unforeseen", "moving", "events", "goal")]
    for w in result.items:
        c = w.counts()
        rows.append((c["name"], f"{w.size[0]:g} x {w.size[1]:g}", c["walls"], c["obstacles"], c["unforeseen"],
                     c["moving"], len(w.events), "moving" if c["moving_goal"] else "fixed"))
    widths = [max(len(str(r[i])) for r in rows) for i in range(len(rows[0]))]
    for r in rows:
        print("  ".join(str(v).ljust(wd) if i < 2 else str(v).rjust(wd) for i, (v, wd) in enumerate(zip(r, widths))))
    for path in written:
        print(f"wrote {path}")


def generate(args) -> None:
    """``--generate FAMILY --seed N [--difficulty D] --out FILE [--plot PNG] [--json]``: the world file,
    written atomically, and its counts and difficulty measures."""
    from ekm.api.checks import choice, output_path, plot_path
    from ekm.api.worlds import generate as make
    from ekm.errors import InputError
    from ekm.provenance import provenance
    from robots.generator import FAMILIES, family_of
    from robots.worldfile import save_world

    if family_of(args.generate) is None:  # a family, or a combination A+B (large+traffic)
        choice(args.generate, FAMILIES.names(), "--generate", "ekm worlds")
    if args.check:
        raise InputError("ekm worlds: argument --check: not with --generate")
    for option in ("seed", "out"):
        if getattr(args, option) is None:
            raise InputError(f"ekm worlds: argument --generate: needs --{option}")
    out = output_path(args.out, "--out", ".json")
    png = plot_path(args.plot, "--plot") if args.plot else None
    world = make(args.generate, args.seed, args.difficulty)
    try:
        save_world(world, out)
    except OSError as exc:
        raise InputError(f"--out {out}: cannot write ({exc.strerror or exc})") from None
    if png is not None:
        from robots.plot import plot_world, save_figure

        save_figure(plot_world(world).figure, png)
    d = world.difficulty
    if args.json:
        print_json({**world.counts(), "difficulty": d.to_dict(), "out": str(out), **provenance(jax=False)})
        return
    c = world.counts()
    print(f"{world.name}: {d.family}, seed {d.seed}, difficulty {d.level:g}; {world.size[0]:g} x {world.size[1]:g} m, "
          f"{c['walls']} walls, {c['unforeseen']} unforeseen, {c['moving']} moving")
    print(f"  narrowest passage {d.narrowest_passage_m:.3f} m, route {d.route_length_m:.3f} m "
          f"({d.route_ratio:.2f} x the straight {d.straight_m:.3f} m), {d.turns} turns, {d.traps} traps")
    print(f"wrote {out}")
    if png is not None:
        print(f"wrote {png}")
