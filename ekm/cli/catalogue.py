"""``ekm architectures``, ``ekm players``, ``ekm families``: everything ekm knows of one kind — built in, from
installed packages, added in Python — each with its summary and its parameters (:mod:`ekm.api.catalogue`), listed
by the one :class:`Catalogue` command."""

from __future__ import annotations

import textwrap
from dataclasses import dataclass
from typing import Callable

from ekm.cli.args import command, print_json


@dataclass(frozen=True)
class Catalogue:
    """The command ``ekm NAME``: it lists the rows of ``ekm.api.catalogue.NAME()``, one ``kind`` each, headed by
    ``title(row)``; ``summary``, ``examples`` and ``more`` are its help."""

    name: str
    kind: str
    summary: str
    examples: tuple
    more: str
    title: Callable[[dict], str]

    def add_parser(self, sub) -> None:
        p = command(sub, self.name, self.summary, list(self.examples), more=self.more)
        p.add_argument("names", nargs="*", metavar="NAME", help=f"only these {self.name} (default: all)")
        p.add_argument("--json", action="store_true", help="print JSON")
        p.set_defaults(func=self.run)

    def run(self, args) -> None:
        """Print the rows named in ``args.names`` (all if none; an unknown one is an InputError) — each its title,
        summary and parameters with defaults and allowed values — or ``{NAME: rows}`` as JSON."""
        from ekm.api import catalogue
        from ekm.errors import InputError

        table = getattr(catalogue, self.name)()
        unknown = [n for n in args.names if n not in table.names()]
        if unknown:
            raise InputError(f"{self.kind} {unknown[0]!r}: unknown (choose from {', '.join(table.names())})")
        rows = [r for r in table.rows if not args.names or r["name"] in args.names]
        if args.json:
            print_json({self.name: rows})
            return
        for i, r in enumerate(rows):
            print(("\n" if i else "") + self.title(r))
            print(textwrap.fill(r["summary"], 100, initial_indent="  ", subsequent_indent="  "))
            width = max((len(p["name"]) for p in r["parameters"]), default=0)
            for p in r["parameters"]:
                allowed = f" [{'|'.join(p['choices'])}]" if p["choices"] else f" ({p['type']})"
                head = f"    {p['name']:<{width}} = {p['default']}{allowed}"
                print(head + (f"  {p['help']}" if p["help"] else ""))


def _architecture(r: dict) -> str:
    drives = f"drives a {' or '.join(r['map'])}-chart EKM" if r["map"] else "drives no EKM"
    encodes = f"; {r['encoding']} responses" if r["encoding"] else ""
    return f"{r['name']} ({r['origin']}; {drives}{encodes})"


def _plain(r: dict) -> str:
    return f"{r['name']} ({r['origin']})"


ARCHITECTURES = Catalogue(
    "architectures", "architecture", "list the architectures with their parameters, defaults and allowed values",
    ("ekm architectures", "ekm architectures fields", "ekm architectures --json"),
    "Spell one as NAME or NAME:k=v,k=v (ekm run --architecture fields:form=thesis). Add your own: "
    "docs/guide/architectures.md.", _architecture)

PLAYERS = Catalogue(
    "players", "player", "list the soccer players with their parameters, defaults and allowed values",
    ("ekm players", "ekm players deliberation", "ekm players --json"),
    "Spell one as NAME or NAME:k=v,k=v (ekm match deliberation deliberation:level=half). "
    "docs/guide/soccer.md describes them, and how to add your own.", _plain)

FAMILIES = Catalogue(
    "families", "family", "list the families of generated worlds",
    ("ekm families", "ekm families maze", "ekm families --json"),
    "A family's world is spelt FAMILY:SEED or FAMILY:SEED:D (D, the difficulty, in [0, 1]) wherever a world is "
    "named (--world maze:7); ekm worlds --generate maze --seed 7 --out maze7.json writes its file. Add your own: "
    "docs/guide/worlds.md.", _plain)
