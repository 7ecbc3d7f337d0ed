"""``ekm worlds``: list the named worlds, or validate world files (``--check``); draw them with
``--plot DIR``."""

from __future__ import annotations

from ekm.cli.args import print_json, provenance
from ekm.errors import InputError


def add_parser(sub) -> None:
    p = sub.add_parser("worlds", help="list, check and draw worlds")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.add_argument("--plot", metavar="DIR", help="draw each world to DIR/NAME.png")
    p.add_argument("--check", metavar="FILE", nargs="+", help="validate world files (exit 2 on the first bad one)")
    p.set_defaults(func=run)


def run(args) -> None:
    """List the named worlds, or validate world files (``--check``); draw them with ``--plot DIR``.

    Every file is validated before anything is drawn or printed, so a bad file (exit 2) leaves no output
    behind; each PNG is written atomically.
    """
    from robots.worldfile import load_world, named_worlds

    worlds = [load_world(p) for p in args.check] if args.check else [load_world(n) for n in named_worlds()]
    written = _plot_worlds(worlds, args.plot) if args.plot else []
    if args.json:
        print_json({"worlds": [w.counts() for w in worlds], **provenance(jax=False)})
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
