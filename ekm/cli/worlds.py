"""``ekm worlds``: list the named worlds, or validate world files (``--check``); draw them with
``--plot DIR``."""

from __future__ import annotations

from ekm.cli.args import print_json


def add_parser(sub) -> None:
    p = sub.add_parser("worlds", help="list, check and draw worlds")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.add_argument("--plot", metavar="DIR", help="draw each world to DIR/NAME.png")
    p.add_argument("--check", metavar="FILE", nargs="+", help="validate world files (exit 2 on the first bad one)")
    p.set_defaults(func=run)


def run(args) -> None:
    """List the named worlds, or validate world files (``--check``); draw them with ``--plot DIR``
    (:func:`ekm.worlds`).

    Every file is validated before anything is drawn or printed, so a bad file (exit 2) leaves no output
    behind; each PNG is written atomically.
    """
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
