"""``ekm players``: every soccer player ``ekm match`` and ``ekm tournament`` know, with its summary and its
parameters (:func:`ekm.players`)."""

from __future__ import annotations

from ekm.cli.args import command


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
    from ekm.cli.architectures import print_catalogue

    print_catalogue(players(), args, "player", "players", lambda r: r["name"])
