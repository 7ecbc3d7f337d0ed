"""``ekm players``: every soccer player ``ekm match`` and ``ekm tournament`` know, with its summary and its
parameters (:func:`ekm.players`)."""

from __future__ import annotations

import textwrap

from ekm.cli.args import command, print_json


def add_parser(sub) -> None:
    p = command(sub, "players", "list the soccer players with their parameters, defaults and allowed values",
                ["ekm players", "ekm players deliberation", "ekm players --json"],
                more="Spell one as NAME or NAME:k=v,k=v (ekm match deliberation deliberation:level=half). "
                     "docs/guide/soccer.md describes them.")
    p.add_argument("names", nargs="*", metavar="NAME", help="only these players (default: all)")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=run)


def run(args) -> None:
    """Print the players (or the JSON of :func:`ekm.players`)."""
    from ekm.api.soccer import players
    from ekm.errors import InputError

    table = players()
    unknown = [n for n in args.names if n not in table.names()]
    if unknown:
        raise InputError(f"player {unknown[0]!r}: unknown (choose from {', '.join(table.names())})")
    rows = [r for r in table.rows if not args.names or r["name"] in args.names]
    if args.json:
        print_json({"players": rows})
        return
    for i, r in enumerate(rows):
        print(("\n" if i else "") + r["name"])
        print(textwrap.fill(r["summary"], 100, initial_indent="  ", subsequent_indent="  "))
        width = max((len(p["name"]) for p in r["parameters"]), default=0)
        for p in r["parameters"]:
            allowed = f" [{'|'.join(p['choices'])}]" if p["choices"] else f" ({p['type']})"
            head = f"    {p['name']:<{width}} = {p['default']}{allowed}"
            print(head + (f"  {p['help']}" if p["help"] else ""))
