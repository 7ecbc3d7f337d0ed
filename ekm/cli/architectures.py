"""``ekm architectures``: every architecture ``ekm run`` and ``ekm compare`` know — built in, from installed
packages, added in Python — with its summary and its parameters (:func:`ekm.architectures`)."""

from __future__ import annotations

import textwrap

from ekm.cli.args import command, print_json


def add_parser(sub) -> None:
    p = command(sub, "architectures", "list the architectures with their parameters, defaults and allowed values",
                ["ekm architectures", "ekm architectures fields", "ekm architectures --json"],
                more="Spell one as NAME or NAME:k=v,k=v (ekm run --architecture fields:form=thesis). Add your own: "
                     "docs/guide/architectures.md.")
    p.add_argument("names", nargs="*", metavar="NAME", help="only these architectures (default: all)")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=run)


def run(args) -> None:
    """Print the architectures (or the JSON of :func:`ekm.architectures`)."""
    from ekm.api.architectures import architectures

    def title(r: dict) -> str:
        drives = f"drives a {' or '.join(r['map'])}-chart EKM" if r["map"] else "drives no EKM"
        encodes = f"; {r['encoding']} responses" if r["encoding"] else ""
        return f"{r['name']} ({r['origin']}; {drives}{encodes})"

    print_catalogue(architectures(), args, "architecture", "architectures", title)


def print_catalogue(table, args, what: str, key: str, title) -> None:
    """Print the rows of ``table`` named in ``args.names`` (all if none; an unknown one is an InputError) — each
    its ``title(row)``, summary and parameters with defaults and allowed values — or ``{key: rows}`` as JSON."""
    from ekm.errors import InputError

    unknown = [n for n in args.names if n not in table.names()]
    if unknown:
        raise InputError(f"{what} {unknown[0]!r}: unknown (choose from {', '.join(table.names())})")
    rows = [r for r in table.rows if not args.names or r["name"] in args.names]
    if args.json:
        print_json({key: rows})
        return
    for i, r in enumerate(rows):
        print(("\n" if i else "") + title(r))
        print(textwrap.fill(r["summary"], 100, initial_indent="  ", subsequent_indent="  "))
        width = max((len(p["name"]) for p in r["parameters"]), default=0)
        for p in r["parameters"]:
            allowed = f" [{'|'.join(p['choices'])}]" if p["choices"] else f" ({p['type']})"
            head = f"    {p['name']:<{width}} = {p['default']}{allowed}"
            print(head + (f"  {p['help']}" if p["help"] else ""))
